#include "sim_hw/real_sheet/curvature_bending.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "sim_hw/real_sheet/cross_matrix.h"

namespace sim_hw::real_sheet {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;
using Vec15 = Eigen::Matrix<double, 15, 1>;
using Mat15 = Eigen::Matrix<double, 15, 15>;

// First- and second-derivative weights on three nodes spaced a, b apart.
void derivative_weights(double a, double b, double first[3], double second[3]) {
  first[0] = -b / (a * (a + b));
  first[1] = (b - a) / (a * b);
  first[2] = a / (b * (a + b));
  second[0] = 2.0 / (a * (a + b));
  second[1] = -2.0 / (a * b);
  second[2] = 2.0 / (b * (a + b));
}

// The five difference vectors (x_uu, x_vv, x_uv, x_u, x_v) as y = L x with L = C (x) I3; C is
// 5 x 9 over the stencil's nodes.
Eigen::Matrix<double, 5, 9> difference_weights(const BendingNode& node) {
  double du1[3], du2[3], dv1[3], dv2[3];
  derivative_weights(node.du_before_m, node.du_after_m, du1, du2);
  derivative_weights(node.dv_before_m, node.dv_after_m, dv1, dv2);
  Eigen::Matrix<double, 5, 9> C = Eigen::Matrix<double, 5, 9>::Zero();
  for (int dj = 0; dj < 3; ++dj) {
    for (int di = 0; di < 3; ++di) {
      const int s = 3 * dj + di;
      if (dj == 1) C(0, s) = du2[di], C(3, s) = du1[di];
      if (di == 1) C(1, s) = dv2[dj], C(4, s) = dv1[dj];
      C(2, s) = du1[di] * dv1[dj];
    }
  }
  return C;
}

Vec15 differences(const Vec27& x, const Eigen::Matrix<double, 5, 9>& C) {
  Vec15 y = Vec15::Zero();
  for (int v = 0; v < 5; ++v) {
    for (int s = 0; s < 9; ++s) {
      if (C(v, s) != 0.0) y.segment<3>(3 * v) += C(v, s) * x.segment<3>(3 * s);
    }
  }
  return y;
}

}  // namespace

Eigen::Vector3d stencil_curvature(const Vec27& x, const BendingNode& node) {
  const Vec15 y = differences(x, difference_weights(node));
  const Vec3 n = y.segment<3>(9).cross(y.segment<3>(12)).normalized();
  return Vec3(y.segment<3>(0).dot(n), y.segment<3>(3).dot(n), 2.0 * y.segment<3>(6).dot(n)) - node.rest_k_1_m;
}

double curvature_bending_energy(const Vec27& x, const BendingNode& node, const Mat3& D, double beta,
                                Vec27* gradient, Mat27* hessian, Hessian kind) {
  const Eigen::Matrix<double, 5, 9> C = difference_weights(node);
  const Vec15 y = differences(x, C);
  const Vec3 p = y.segment<3>(9), q = y.segment<3>(12);
  const Vec3 N = p.cross(q);
  const double nu = N.norm();
  const Vec3 n = N / nu;
  const double scale[3] = {1.0, 1.0, 2.0};  // k3 = 2 x_uv . n
  Vec3 k;
  for (int i = 0; i < 3; ++i) k[i] = scale[i] * y.segment<3>(3 * i).dot(n) - node.rest_k_1_m[i];
  const Vec3 W(1.0, 1.0, 0.5);  // |k|^2 = k^T diag(W) k
  const Vec3 Dk = D * k, Wk = W.cwiseProduct(k);
  const double Q = k.dot(Dk), F = k.dot(Wk);
  const double energy = node.area_m2 * 0.5 * Q * (1.0 + 0.5 * beta * F);
  if (!gradient && !hessian) return energy;

  // m = dpsi/dk, Psi = d2psi/dk2 (see the header's energy).
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
    J.block<1, 3>(i, 3 * i) = scale[i] * n.transpose();
    J.block<1, 3>(i, 9) = scale[i] * (Jp.transpose() * gN).transpose();
    J.block<1, 3>(i, 12) = scale[i] * (Jq.transpose() * gN).transpose();
  }
  const Vec15 gy = node.area_m2 * J.transpose() * m;
  if (gradient) {
    gradient->setZero();
    for (int v = 0; v < 5; ++v) {
      for (int s = 0; s < 9; ++s) {
        if (C(v, s) != 0.0) gradient->segment<3>(3 * s) += C(v, s) * gy.segment<3>(3 * v);
      }
    }
  }
  if (!hessian) return energy;

  Mat15 Hy;
  if (kind == Hessian::kProjected) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(Psi);
    Psi = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
    Hy = node.area_m2 * J.transpose().lazyProduct(Psi * J);
  } else {
    Hy = node.area_m2 * J.transpose().lazyProduct(Psi * J);
    // + sum_i m_i d2k_i/dy2.
    for (int i = 0; i < 3; ++i) {
      const double c = node.area_m2 * m[i] * scale[i];
      const Vec3 w = y.segment<3>(3 * i);
      const double wn = w.dot(n);
      const Vec3 gN = P * w / nu;
      // d2(w . n)/dN2 = -(w n^T + n w^T + (w . n)(I - 3 n n^T)) / |N|^2
      const Mat3 HN = -(w * n.transpose() + n * w.transpose() + wn * (Mat3::Identity() - 3.0 * n * n.transpose())) /
                      (nu * nu);
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
  }
  // H_x = L^T H_y L with L = C (x) I3: block (s, t) = sum over v, w of C(v, s) C(w, t) H_y(v, w),
  // over the few non-zero weights of each stencil node.
  int uses[9][5], use_count[9] = {};
  for (int t = 0; t < 9; ++t) {
    for (int v = 0; v < 5; ++v) {
      if (C(v, t) != 0.0) uses[t][use_count[t]++] = v;
    }
  }
  for (int t = 0; t < 9; ++t) {
    for (int s = 0; s <= t; ++s) {
      Mat3 block = Mat3::Zero();
      for (int a = 0; a < use_count[s]; ++a) {
        for (int b = 0; b < use_count[t]; ++b) {
          const int v = uses[s][a], w = uses[t][b];
          block += (C(v, s) * C(w, t)) * Hy.block<3, 3>(3 * v, 3 * w);
        }
      }
      hessian->block<3, 3>(3 * s, 3 * t) = block;
      if (s != t) hessian->block<3, 3>(3 * t, 3 * s) = block.transpose();
    }
  }
  return energy;
}

}  // namespace sim_hw::real_sheet
