#include "sim_hw/spline_shell/membrane_point.h"

#include <Eigen/Eigenvalues>

namespace sim_hw::spline_shell {

Eigen::Vector3d green_lagrange_strain(const Vec6& y) {
  const Eigen::Vector3d a1 = y.head<3>(), a2 = y.tail<3>();
  return Eigen::Vector3d(0.5 * (a1.squaredNorm() - 1.0), 0.5 * (a2.squaredNorm() - 1.0), a1.dot(a2));
}

double membrane_density(const Vec6& y, const Eigen::Matrix3d& K, const Eigen::Vector3d& e0, Vec6* gradient,
                        Mat6* hessian, Hessian kind) {
  const Eigen::Vector3d a1 = y.head<3>(), a2 = y.tail<3>();
  const Eigen::Vector3d de = green_lagrange_strain(y) - e0;
  const Eigen::Vector3d S = K * de;  // (S_uu, S_vv, S_uv), N/m
  const double energy = 0.5 * de.dot(S);
  if (!gradient && !hessian) return energy;
  // J = de/dy: rows (a1^T, 0), (0, a2^T), (a2^T, a1^T).
  Eigen::Matrix<double, 3, 6> J = Eigen::Matrix<double, 3, 6>::Zero();
  J.block<1, 3>(0, 0) = a1.transpose();
  J.block<1, 3>(1, 3) = a2.transpose();
  J.block<1, 3>(2, 0) = a2.transpose();
  J.block<1, 3>(2, 3) = a1.transpose();
  if (gradient) *gradient = J.transpose() * S;
  if (!hessian) return energy;
  // Geometric term: sum_i S_i d2e_i/dy2 = [[S_uu, S_uv], [S_uv, S_vv]] (x) I3.
  Eigen::Matrix2d stress;
  stress << S[0], S[2], S[2], S[1];
  if (kind == Hessian::kProjected) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(stress);
    stress = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
  }
  *hessian = J.transpose() * K * J;
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) hessian->block<3, 3>(3 * a, 3 * b).diagonal().array() += stress(a, b);
  }
  return energy;
}

}  // namespace sim_hw::spline_shell
