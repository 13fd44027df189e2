#pragma once
// Hinge stiffnesses that make discrete hinge bending reproduce the continuum plate energy.
//
// A plate bent into a cylinder of curvature kappa along direction d stores D(d)/2 kappa^2 per
// unit area. A hinge e stores k_e theta_e^2 with theta_e = kappa t_e(d) + O(kappa^3), and t_e(d)
// depends on how the edge is oriented against d: on a right-triangle grid the same k gives
// energies several-fold off and tens of percent apart between the axes and the diagonal.
// We set
//   k_e = w_e (a n_u^2 + b n_v^2),   w_e = |e|^2 / Abar_e,
// with Abar_e a third of the rest area of the hinge's two triangles and n the unit normal of the
// edge in material coordinates, and solve for (a, b) per mesh so that cylinders along u and v
// store exactly D_u/2 kappa^2 and D_v/2 kappa^2 per unit of the hinges' area sum(Abar_e).
// On the offset-row mesh other directions then match D within a few percent (tested).
// Bending with curvature in two directions at once behaves as a plate with Poisson ratio about
// -1/3 whatever the material's: on equilateral triangles a hinge sees kappa_nn - kappa_tt / 3,
// so a sphere costs less than two cylinders and a bent strip curls its edges the same way
// (synclastic) instead of into a saddle. Beam-like bending depends on nu^2 only and is
// unaffected (cantilever test); doubly curved shapes are not.

#include <vector>

#include "twin/model/hinge_bending.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

class BendingCalibration {
 public:
  BendingCalibration(const SheetMesh& mesh, const std::vector<Hinge>& hinges);

  // k_e (N*m) per hinge for plate rigidities D_u, D_v (N*m). Throws std::invalid_argument when
  // the anisotropy is beyond what hinges on this mesh can represent with positive stiffness.
  std::vector<double> hinge_stiffnesses(double rigidity_u_Nm, double rigidity_v_Nm) const;

  double hinge_area_m2() const { return hinge_area_m2_; }

 private:
  std::vector<double> weight_;  // w_e (dimensionless)
  std::vector<Vec2> normal_;    // n_e
  double hinge_area_m2_ = 0.0;
  Mat2 to_coefficients_;        // (a, b) = to_coefficients_ * (D_u, D_v)
  double isotropic_factor_ = 0.0;  // fallback a = b = factor * D for degenerate tiny meshes
};

// The rest mesh wrapped on a cylinder whose curvature (1/m) acts along the material direction at
// `angle_rad` from u; the sheet stays unstretched. Positions stacked 3n (m).
VecX wrap_on_cylinder(const SheetMesh& mesh, double angle_rad, double curvature_1_m);

// Plate rigidity (N*m) that hinges with stiffnesses k show for a cylinder along `angle_rad`:
// the discrete energy divided by kappa^2/2 times the hinges' area, in the small-curvature limit.
double effective_cylinder_rigidity(const SheetMesh& mesh, const std::vector<Hinge>& hinges,
                                   const std::vector<double>& stiffnesses, double angle_rad);

}  // namespace twin
