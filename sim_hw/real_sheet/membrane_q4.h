#pragma once
// Membrane energy of one bilinear quadrilateral (Q4) cell of the grid, integrated with 2 x 2
// Gauss points: sum over the points of (du dv / 4) * 1/2 (e - e0)^T K (e - e0), with e the
// Green-Lagrange strain (E_uu, E_vv, 2 E_uv) of the bilinear interpolant there.
//   Elastic membrane: K = C (N/m), e0 = 0 (flat, unstrained rest state).
//   Strain-rate viscosity over an implicit step of dt: K = C_visc / dt (N/m), e0 = the strain at
//   the step's start, the dissipation potential of sigma_v = C_visc de/dt.
// Cell nodes, counter-clockwise in (u, v): (i, j), (i+1, j), (i+1, j+1), (i, j+1); positions
// stacked [x0 y0 z0 x1 ...] (12), gradient in N, Hessian in N/m.
// Projected Hessian: the second Piola-Kirchhoff stress in the geometric stiffness is clipped to
// its tensile part (a tension-field membrane), so the block is positive semi-definite.

#include <array>

#include <Eigen/Core>

namespace sim_hw::real_sheet {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

enum class Hessian { kExact, kProjected };

// Strains at the four Gauss points (each (E_uu, E_vv, 2 E_uv)).
std::array<Eigen::Vector3d, 4> q4_strains(const Vec12& x, double du_m, double dv_m);

// Energy (J); fills gradient and Hessian when non-null. e0 null: the unstrained rest state.
double q4_membrane_energy(const Vec12& x, double du_m, double dv_m, const Eigen::Matrix3d& K_N_m,
                          const std::array<Eigen::Vector3d, 4>* e0, Vec12* gradient, Mat12* hessian,
                          Hessian kind = Hessian::kExact);

}  // namespace sim_hw::real_sheet
