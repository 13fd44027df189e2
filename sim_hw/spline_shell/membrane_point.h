#pragma once
// The membrane energy density at one point of the reference sheet, from the surface's tangents
// there: y = (x_u, x_v) (6 values; the flat rest state has x_u, x_v orthonormal, since the
// material coordinates u, v are arc lengths of the flat sheet). Green-Lagrange strain
//   e = (E_uu, E_vv, 2 E_uv) = ((x_u.x_u - 1)/2, (x_v.x_v - 1)/2, x_u.x_v),
//   psi = 1/2 (e - e0)^T K (e - e0)   (J/m^2),
// with K (N/m) the orthotropic plane-stress matrix C (elastic, e0 = 0) or C_visc / dt with e0 the
// strain at an implicit step's start (the strain-rate viscosity's dissipation potential).
// Gradient (N/m per unit of y) and Hessian. The projected Hessian clips the second
// Piola-Kirchhoff stress S = K (e - e0) in the geometric term to its tensile part (a
// tension-field membrane), so it is positive semi-definite.

#include <Eigen/Core>

#include "sim_hw/real_sheet/membrane_q4.h"  // Hessian

namespace sim_hw::spline_shell {

using real_sheet::Hessian;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

Eigen::Vector3d green_lagrange_strain(const Vec6& y);

double membrane_density(const Vec6& y, const Eigen::Matrix3d& K_N_m, const Eigen::Vector3d& e0, Vec6* gradient,
                        Mat6* hessian, Hessian kind = Hessian::kExact);

}  // namespace sim_hw::spline_shell
