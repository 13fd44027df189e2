#pragma once
// Discrete hinge bending energy of one interior edge (Grinspun et al. 2003, with the exact
// derivatives of Tamstorf and Grinspun 2013; paper section 3.2, Eq. 10):
//   psi(theta) = k (theta - theta_rest)^2                                  (J)
//   gradient   = 2 k (theta - theta_rest) grad theta
//   Hessian    = 2 k grad theta grad theta^T + 2 k (theta - theta_rest) Hess theta
// The stiffness k (N*m) of each hinge comes from bending_calibration.h so that the sum over
// hinges equals the continuum plate energy D/2 kappa^2 for cylinders along u and v.
// kProjected drops the second Hessian term (Gauss-Newton), which is positive semi-definite.
// DOF order: (x0, x1, x2, x3) as in dihedral_angle.h.

#include <array>
#include <vector>

#include "twin/sheet_mesh.h"
#include "twin/types.h"

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
};

// Energy (J); writes gradient (N) and Hessian (N/m) when non-null. NaN for a degenerate hinge.
double hinge_bending_energy(const HingeElement& h, const Vec12& xh, Vec12* grad, Mat12* hess,
                            HessianMode mode);

}  // namespace twin
