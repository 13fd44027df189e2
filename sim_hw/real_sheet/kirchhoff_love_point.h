#pragma once
// The Kirchhoff-Love bending energy density at one point of a surface, from the surface's
// derivatives there: y = (x_uu, x_vv, x_uv, x_u, x_v) (15 values, m^-1 for the second and 1 for
// the first derivatives in material coordinates), n = x_u x x_v / |x_u x x_v|,
//   k = (x_uu . n, x_vv . n, 2 x_uv . n) - k_rest   (1/m),
//   psi = 1/2 k^T D k (1 + beta/2 |k|^2),  |k|^2 = k1^2 + k2^2 + k3^2 / 2   (J/m^2),
// with D the 3 x 3 bending matrix (N*m) and beta (m^2) the stiffening. Shared by the two
// discretisations that produce y: the lab plate's finite-difference stencils
// (curvature_bending.h) and the reference's B-spline quadrature points (sim_hw/spline_shell).
// Gradient in J/m^2 per unit of y, Hessian likewise. The projected Hessian is the Gauss-Newton
// part with the constitutive Hessian d2psi/dk2 clipped to positive semi-definite.

#include <Eigen/Core>

#include "sim_hw/real_sheet/membrane_q4.h"  // Hessian

namespace sim_hw::real_sheet {

using Vec15 = Eigen::Matrix<double, 15, 1>;
using Mat15 = Eigen::Matrix<double, 15, 15>;

Eigen::Vector3d kirchhoff_love_curvature(const Vec15& y, const Eigen::Vector3d& rest_k_1_m);

double kirchhoff_love_density(const Vec15& y, const Eigen::Vector3d& rest_k_1_m, const Eigen::Matrix3d& D_Nm,
                              double beta_m2, Vec15* gradient, Mat15* hessian, Hessian kind = Hessian::kExact);

}  // namespace sim_hw::real_sheet
