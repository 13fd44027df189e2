#pragma once
// Plate bending of one triangle from the dihedral angles of its edges: a discrete second
// fundamental form per triangle that carries the full orthotropic plate rigidity D (N*m),
//   D = [[D11, D12, 0], [D12, D22, 0], [0, 0, D66]]  on  kappa = (K_uu, K_vv, 2 K_uv),
// the curvature tensor K (1/m) in the material frame. The continuum energy density is
// 1/2 kappa^T D kappa (J/m^2).
//
// Why not hinges alone: a hinge's energy k theta^2 sees only its own edge's angle, so a sheet
// bent in two directions at once behaves like a plate whose Poisson ratio (D12) and twist
// stiffness (D66) are fixed by the mesh (about -1/3 on equilateral triangles,
// bending_calibration.h), whatever the material. Here the three angles of a triangle's edges
// are read together as one curvature tensor, so D12 and D66 are the material's.
//
// The triangle's curvature from its angles: to first order a hinge's angle is linear in a
// constant curvature of the surface around it, theta_j = A_j . kappa (A_j from the rest
// geometry, rest_curvature.h; A is m x 3 for the m edges of the triangle that have a
// neighbour). With three such edges A is invertible and kappa = A^-1 theta reproduces every
// constant curvature exactly, on any triangulation (the per-triangle shape operator of
// Grinspun et al. 2006 is exact on equilateral triangles only). A triangle on a free edge has
// fewer angles than curvature components; of the curvatures its angles allow we take the one of
// least energy (a free edge carries no bending moment), which for m = 3 is A^-1 theta as well:
//   kappa(d) = M d,   M = D^-1 A^T (A D^-1 A^T)^-1      (1/m per rad)
//   psi = 1/2 d^T Q d (1 + beta/2 |K|^2),   Q = Abar (A D^-1 A^T)^-1   (N*m)
// with d = theta - theta_rest, theta_rest = A kappa_rest (a sheet curved at rest,
// rest_curvature.h), Abar the triangle's rest area and |K|^2 = d^T R d, R = M^T P M,
// P = diag(1, 1, 1/2), the Frobenius norm of the curvature tensor, for the optional stiffening
// M = D kappa (1 + beta |K|^2) in its isotropic form (beta in m^2, bending_stiffening.h).
// Summed over triangles this is the continuum energy for every constant curvature (interior
// triangles), which the hinge model reaches only for cylinders along u and v.
//
// Gradient and Hessian through the exact derivatives of the angles (dihedral_angle.h):
//   grad = sum_j psi_j grad theta_j,
//   Hess = sum_jk psi_jk grad theta_j grad theta_k^T + sum_j psi_j Hess theta_j
// (psi_j, psi_jk the derivatives in d). kProjected keeps the first sum with psi_jk's negative
// eigenvalues clipped (Gauss-Newton), which is positive semi-definite.
//
// The in-plane geometry (A, Abar) is the rest triangle's: the membrane of a prepreg stretches
// by well under a percent, and the error is of that order.
//
// DOF order of the 18-vector: the triangle's vertices t0, t1, t2, then o0, o1, o2, the vertex
// across edge k = (t_{k+1}, t_{k+2}) from t_k. An edge without a neighbour has a stand-in vertex
// there (any other vertex of the mesh) whose derivatives are zero.

#include <array>

#include "twin/base/types.h"

namespace twin {

using Vec18 = Eigen::Matrix<double, 18, 1>;
using Mat18 = Eigen::Matrix<double, 18, 18>;

struct PlateElement {
  std::array<int, 6> v{-1, -1, -1, -1, -1, -1};
  int hinge_count = 0;          // m: edges with a neighbour, listed first in `edge`
  std::array<int, 3> edge{};    // local edge k (0..2) of hinge j
  Mat3 q = Mat3::Zero();        // Q (N*m), top-left m x m used
  Mat3 r = Mat3::Zero();        // R (1/m^2 per rad^2), for the stiffening
  Vec3 rest_angle_rad = Vec3::Zero();  // theta_rest of hinge j
  double stiffening_m2 = 0.0;   // beta
};

// Energy (J); writes gradient (N) and Hessian (N/m) when non-null. NaN for a degenerate hinge.
double plate_bending_energy(const PlateElement& e, const Vec18& x, Vec18* grad, Mat18* hess,
                            HessianMode mode);

// The hinge's vertices (x0, x1, x2, x3 of dihedral_angle.h) as local indices of the element for
// local edge k: x0 = t_{k+1}, x1 = t_{k+2}, x2 = t_k, x3 = o_k.
std::array<int, 4> plate_hinge_local_vertices(int k);

}  // namespace twin
