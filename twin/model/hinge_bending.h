#pragma once
// Discrete hinge bending energy of one interior edge (Grinspun et al. 2003, with the exact
// derivatives of Tamstorf and Grinspun 2013; paper section 3.2, Eq. 10), with an optional
// quartic (stiffening) part (bending_stiffening.h). With d = theta - theta_rest:
//   psi(theta) = k (d^2 + q d^4)                                           (J)
//   gradient   = psi'(d) grad theta,            psi'  = 2 k d (1 + 2 q d^2)
//   Hessian    = psi''(d) grad theta grad theta^T + psi'(d) Hess theta,
//                                               psi'' = 2 k (1 + 6 q d^2)
// q = 0 is the paper's hinge (and costs the same). The stiffness k (N*m) of each hinge comes
// from bending_calibration.h so that the sum over hinges equals the continuum plate energy
// D/2 kappa^2 for cylinders along u and v; theta_rest from rest_curvature.h.
// kProjected drops the psi' Hess theta term (Gauss-Newton); psi'' > 0 for q >= 0, so what is
// left is positive semi-definite, with or without rest angles and stiffening.
// DOF order: (x0, x1, x2, x3) as in dihedral_angle.h.

#include <array>
#include <vector>

#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

// Topology of a hinge: edge (v[0], v[1]) as it runs counter-clockwise in triangle_a, v[2] the
// third vertex of triangle_a, v[3] the third vertex of triangle_b.
struct Hinge {
  std::array<int, 4> v{};
  int triangle_a = -1;
  int triangle_b = -1;
};

// Every interior edge of the mesh. Throws std::invalid_argument for an edge shared by more than
// two triangles or by two triangles of opposite orientation.
std::vector<Hinge> build_hinges(const SheetMesh& mesh);

struct HingeElement {
  std::array<int, 4> v{};
  double stiffness_Nm = 0.0;    // k
  double rest_angle_rad = 0.0;  // theta_rest; 0 for a sheet flat at rest
  double quartic_per_rad2 = 0.0;  // q >= 0 (1/rad^2); 0 without bending stiffening
};

// Energy (J); writes gradient (N) and Hessian (N/m) when non-null. NaN for a degenerate hinge.
double hinge_bending_energy(const HingeElement& h, const Vec12& xh, Vec12* grad, Mat12* hess,
                            HessianMode mode);

}  // namespace twin
