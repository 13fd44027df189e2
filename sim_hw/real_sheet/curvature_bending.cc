#include "sim_hw/real_sheet/curvature_bending.h"

#include "sim_hw/real_sheet/kirchhoff_love_point.h"

namespace sim_hw::real_sheet {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

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
  return kirchhoff_love_curvature(differences(x, difference_weights(node)), node.rest_k_1_m);
}

double curvature_bending_energy(const Vec27& x, const BendingNode& node, const Mat3& D, double beta,
                                Vec27* gradient, Mat27* hessian, Hessian kind) {
  const Eigen::Matrix<double, 5, 9> C = difference_weights(node);
  const Vec15 y = differences(x, C);
  Vec15 gy;
  Mat15 Hy;
  const double density = kirchhoff_love_density(y, node.rest_k_1_m, D, beta, gradient ? &gy : nullptr,
                                                hessian ? &Hy : nullptr, kind);
  if (gradient) {
    gy *= node.area_m2;
    gradient->setZero();
    for (int v = 0; v < 5; ++v) {
      for (int s = 0; s < 9; ++s) {
        if (C(v, s) != 0.0) gradient->segment<3>(3 * s) += C(v, s) * gy.segment<3>(3 * v);
      }
    }
  }
  if (!hessian) return node.area_m2 * density;
  Hy *= node.area_m2;
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
  return node.area_m2 * density;
}

}  // namespace sim_hw::real_sheet
