#include "sim_hw/real_sheet/membrane_q4.h"

#include <cmath>

#include <Eigen/Eigenvalues>

namespace sim_hw::real_sheet {
namespace {

struct GaussPoint {
  Eigen::Vector4d dN_du, dN_dv;  // shape-function derivatives (1/m) at the point
};

// The 2 x 2 Gauss points of the cell [0, du] x [0, dv] (at 1/2 -+ 1/(2 sqrt 3) of each side).
std::array<GaussPoint, 4> gauss_points(double du, double dv) {
  constexpr double g0 = 0.21132486540518711775, g1 = 0.78867513459481288225;  // 1/2 -+ 1/(2 sqrt 3)
  const double xi[4] = {g0, g1, g1, g0}, eta[4] = {g0, g0, g1, g1};
  std::array<GaussPoint, 4> points;
  for (int p = 0; p < 4; ++p) {
    const double a = xi[p], b = eta[p];
    // N = ((1-a)(1-b), a(1-b), ab, (1-a)b)
    points[p].dN_du = Eigen::Vector4d(-(1 - b), (1 - b), b, -b) / du;
    points[p].dN_dv = Eigen::Vector4d(-(1 - a), -a, a, (1 - a)) / dv;
  }
  return points;
}

}  // namespace

std::array<Eigen::Vector3d, 4> q4_strains(const Vec12& x, double du_m, double dv_m) {
  std::array<Eigen::Vector3d, 4> e;
  const auto points = gauss_points(du_m, dv_m);
  for (int p = 0; p < 4; ++p) {
    Eigen::Vector3d xu = Eigen::Vector3d::Zero(), xv = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) {
      xu += points[p].dN_du[a] * x.segment<3>(3 * a);
      xv += points[p].dN_dv[a] * x.segment<3>(3 * a);
    }
    e[p] = Eigen::Vector3d(0.5 * (xu.squaredNorm() - 1.0), 0.5 * (xv.squaredNorm() - 1.0), xu.dot(xv));
  }
  return e;
}

double q4_membrane_energy(const Vec12& x, double du_m, double dv_m, const Eigen::Matrix3d& K,
                          const std::array<Eigen::Vector3d, 4>* e0, Vec12* gradient, Mat12* hessian,
                          Hessian kind) {
  const auto points = gauss_points(du_m, dv_m);
  const double weight = 0.25 * du_m * dv_m;  // m^2 per Gauss point
  if (gradient) gradient->setZero();
  if (hessian) hessian->setZero();
  double energy = 0.0;
  for (int p = 0; p < 4; ++p) {
    const Eigen::Vector4d& Nu = points[p].dN_du;
    const Eigen::Vector4d& Nv = points[p].dN_dv;
    Eigen::Vector3d xu = Eigen::Vector3d::Zero(), xv = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) {
      xu += Nu[a] * x.segment<3>(3 * a);
      xv += Nv[a] * x.segment<3>(3 * a);
    }
    const Eigen::Vector3d e(0.5 * (xu.squaredNorm() - 1.0), 0.5 * (xv.squaredNorm() - 1.0), xu.dot(xv));
    const Eigen::Vector3d de = e0 ? Eigen::Vector3d(e - (*e0)[p]) : e;
    const Eigen::Vector3d S = K * de;  // (S_uu, S_vv, S_uv), N/m
    energy += weight * 0.5 * de.dot(S);
    if (!gradient && !hessian) continue;
    // B (3 x 12): rows d(E_uu), d(E_vv), d(2 E_uv) by the node coordinates.
    Eigen::Matrix<double, 3, 12> B;
    for (int a = 0; a < 4; ++a) {
      B.block<1, 3>(0, 3 * a) = Nu[a] * xu.transpose();
      B.block<1, 3>(1, 3 * a) = Nv[a] * xv.transpose();
      B.block<1, 3>(2, 3 * a) = (Nu[a] * xv + Nv[a] * xu).transpose();
    }
    if (gradient) *gradient += weight * B.transpose() * S;
    if (!hessian) continue;
    *hessian += weight * B.transpose().lazyProduct(K * B);
    // Geometric stiffness: sum over nodes a, b of (grad N_a^T S grad N_b) I3, S as a 2 x 2 tensor.
    Eigen::Matrix2d stress;
    stress << S[0], S[2], S[2], S[1];
    if (kind == Hessian::kProjected) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(stress);
      stress = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
    }
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const double s = Nu[a] * (stress(0, 0) * Nu[b] + stress(0, 1) * Nv[b]) +
                         Nv[a] * (stress(1, 0) * Nu[b] + stress(1, 1) * Nv[b]);
        hessian->block<3, 3>(3 * a, 3 * b).diagonal().array() += weight * s;
      }
    }
  }
  return energy;
}

}  // namespace sim_hw::real_sheet
