#include "sim_hw/real_sheet/kirchhoff_love_point.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "sim_hw/real_sheet/cross_matrix.h"

namespace sim_hw::real_sheet {
namespace {
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;
constexpr double kScale[3] = {1.0, 1.0, 2.0};  // k3 = 2 x_uv . n
}  // namespace

Eigen::Vector3d kirchhoff_love_curvature(const Vec15& y, const Eigen::Vector3d& rest_k_1_m) {
  const Vec3 n = y.segment<3>(9).cross(y.segment<3>(12)).normalized();
  return Vec3(y.segment<3>(0).dot(n), y.segment<3>(3).dot(n), 2.0 * y.segment<3>(6).dot(n)) - rest_k_1_m;
}

double kirchhoff_love_density(const Vec15& y, const Eigen::Vector3d& rest_k_1_m, const Mat3& D, double beta,
                              Vec15* gradient, Mat15* hessian, Hessian kind) {
  const Vec3 p = y.segment<3>(9), q = y.segment<3>(12);
  const Vec3 N = p.cross(q);
  const double nu = N.norm();
  const Vec3 n = N / nu;
  Vec3 k;
  for (int i = 0; i < 3; ++i) k[i] = kScale[i] * y.segment<3>(3 * i).dot(n) - rest_k_1_m[i];
  const Vec3 W(1.0, 1.0, 0.5);  // |k|^2 = k^T diag(W) k
  const Vec3 Dk = D * k, Wk = W.cwiseProduct(k);
  const double Q = k.dot(Dk), F = k.dot(Wk);
  const double energy = 0.5 * Q * (1.0 + 0.5 * beta * F);
  if (!gradient && !hessian) return energy;

  // m = dpsi/dk, Psi = d2psi/dk2.
  const Vec3 m = Dk * (1.0 + 0.5 * beta * F) + 0.5 * beta * Q * Wk;
  Mat3 Psi = D * (1.0 + 0.5 * beta * F) + beta * (Dk * Wk.transpose() + Wk * Dk.transpose()) +
             0.5 * beta * Q * Mat3(W.asDiagonal());

  // J = dk/dy (3 x 15). dn/dN = P / |N|, dN/dp = -[q]x, dN/dq = [p]x.
  const Mat3 P = Mat3::Identity() - n * n.transpose();
  const Mat3 Jp = -cross_matrix(q), Jq = cross_matrix(p);
  Eigen::Matrix<double, 3, 15> J = Eigen::Matrix<double, 3, 15>::Zero();
  for (int i = 0; i < 3; ++i) {
    const Vec3 w = y.segment<3>(3 * i);
    const Vec3 gN = P * w / nu;  // d(w . n)/dN
    J.block<1, 3>(i, 3 * i) = kScale[i] * n.transpose();
    J.block<1, 3>(i, 9) = kScale[i] * (Jp.transpose() * gN).transpose();
    J.block<1, 3>(i, 12) = kScale[i] * (Jq.transpose() * gN).transpose();
  }
  if (gradient) *gradient = J.transpose() * m;
  if (!hessian) return energy;

  if (kind == Hessian::kProjected) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(Psi);
    Psi = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
    *hessian = J.transpose().lazyProduct(Psi * J);
    return energy;
  }
  Mat15& Hy = *hessian;
  Hy = J.transpose().lazyProduct(Psi * J);
  // + sum_i m_i d2k_i/dy2.
  for (int i = 0; i < 3; ++i) {
    const double c = m[i] * kScale[i];
    const Vec3 w = y.segment<3>(3 * i);
    const double wn = w.dot(n);
    const Vec3 gN = P * w / nu;
    // d2(w . n)/dN2 = -(w n^T + n w^T + (w . n)(I - 3 n n^T)) / |N|^2
    const Mat3 HN =
        -(w * n.transpose() + n * w.transpose() + wn * (Mat3::Identity() - 3.0 * n * n.transpose())) / (nu * nu);
    const Mat3 dn_dp = P * Jp / nu, dn_dq = P * Jq / nu;
    Hy.block<3, 3>(3 * i, 9) += c * dn_dp;
    Hy.block<3, 3>(9, 3 * i) += c * dn_dp.transpose();
    Hy.block<3, 3>(3 * i, 12) += c * dn_dq;
    Hy.block<3, 3>(12, 3 * i) += c * dn_dq.transpose();
    Hy.block<3, 3>(9, 9) += c * Jp.transpose() * HN * Jp;
    Hy.block<3, 3>(12, 12) += c * Jq.transpose() * HN * Jq;
    // N = p x q is bilinear: d2N_l/dp_m dq_n = eps_lmn, whence -[gN]x.
    const Mat3 pq = Jp.transpose() * HN * Jq - cross_matrix(gN);
    Hy.block<3, 3>(9, 12) += c * pq;
    Hy.block<3, 3>(12, 9) += c * pq.transpose();
  }
  return energy;
}

}  // namespace sim_hw::real_sheet
