#pragma once
// Bending energy at one interior node of the grid: the second fundamental form by finite
// differences on the 3 x 3 stencil around the node (a Kirchhoff-Love plate discretised on a
// tensor-product grid, with the surface normal, not a hinge angle). With spacings a (to the
// node before) and b (to the node after) along u:
//   x_u  = (-b/(a(a+b))) x[i-1] + ((b-a)/(ab)) x[i] + (a/(b(a+b))) x[i+1]   (second order)
//   x_uu = 2 x[i-1]/(a(a+b)) - 2 x[i]/(ab) + 2 x[i+1]/(b(a+b))
// likewise along v, x_uv the product of the u and v first differences on the 3 x 3 nodes
// (on a uniform grid the familiar central differences), n = x_u x x_v / |x_u x x_v|,
//   k = (x_uu . n, x_vv . n, 2 x_uv . n) - k_rest,
//   energy = A * 1/2 k^T D k (1 + beta/2 |k|^2),  |k|^2 = k1^2 + k2^2 + k3^2 / 2
// (A: the node's share of the sheet, m^2; D: 3 x 3 bending matrix, N*m; beta, m^2). For a
// nearly isometric sheet k is the change of curvature in material coordinates; the error of the
// differences is O(h^2) and refining the grid converges to the plate. Free edges: the first
// interior row's energy also covers the half cells out to the edge (see SheetEnergy).
// Stencil node order: (di, dj) for dj = -1..1, di = -1..1, i.e. s = 3 (dj + 1) + (di + 1);
// positions stacked (27), gradient in N, Hessian in N/m. The projected Hessian is the
// Gauss-Newton part with the 3 x 3 constitutive Hessian clipped to positive semi-definite.

#include <Eigen/Core>

#include "sim_hw/real_sheet/membrane_q4.h"

namespace sim_hw::real_sheet {

using Vec27 = Eigen::Matrix<double, 27, 1>;
using Mat27 = Eigen::Matrix<double, 27, 27>;

struct BendingNode {
  double du_before_m = 0.01, du_after_m = 0.01, dv_before_m = 0.01, dv_after_m = 0.01;
  double area_m2 = 1e-4;
  Eigen::Vector3d rest_k_1_m = Eigen::Vector3d::Zero();  // (k_uu, k_vv, 2 k_uv) at rest

  static BendingNode uniform(double du_m, double dv_m, double area_m2) {
    return BendingNode{du_m, du_m, dv_m, dv_m, area_m2, Eigen::Vector3d::Zero()};
  }
};

// The curvature change k (1/m) of the stencil's positions.
Eigen::Vector3d stencil_curvature(const Vec27& x, const BendingNode& node);

double curvature_bending_energy(const Vec27& x, const BendingNode& node, const Eigen::Matrix3d& D_Nm,
                                double beta_m2, Vec27* gradient, Mat27* hessian,
                                Hessian kind = Hessian::kExact);

}  // namespace sim_hw::real_sheet
