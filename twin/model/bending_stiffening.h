#pragma once
// Strain-dependent (stiffening) bending on hinges. The continuum model is a bending moment
// M = D kappa (1 + beta kappa^2), i.e. the energy density D/2 (kappa^2 + beta kappa^4 / 2) with
// beta (m^2) >= 0. A hinge stores
//   psi = k (dtheta^2 + q dtheta^4),   q = beta / (2 d_e^2),   dtheta = theta - theta_rest
// (hinge_bending.h), where d_e (m) converts the hinge's angle into a curvature,
// kappa_e = dtheta / d_e, so that psi = k dtheta^2 (1 + beta kappa_e^2 / 2) mirrors the continuum.
//
// d_e = lambda |t_e| with t_e the hinge's angle per unit curvature across it
// (rest_curvature.h): a hinge's angle responds mostly to the curvature across its edge, and t_e
// carries its size, so kappa_e is a curvature whatever the mesh size. lambda is one number per
// mesh (about 0.85 on the offset-row mesh), set so that cylinders along u and v store, on
// average over the two, exactly (1 + beta kappa^2 / 2) times the quadratic energy in the
// small-curvature limit, with the isotropic hinge stiffnesses of bending_calibration.h as
// weights (so d_e does not depend on D_u, D_v and the energy stays linear in them).
//
// Limit: a quartic of each hinge's angle cannot be isotropic on a mesh with three edge
// directions (the sum of cos^8 over three directions 60 degrees apart is not constant, and the
// hinges' -1/3 coupling to the curvature along them, bending_calibration.h, spreads a cylinder
// that runs between edge families over more hinges with smaller angles). On the offset-row mesh
// the stiffening excess E(beta)/E(0) - 1 is 1.42 times the continuum's beta kappa^2 / 2 for
// cylinders across one edge family (curvature along v or +-30 degrees from u) and 0.58 times it
// between them (along u or +-60 degrees), close to 1 at 15 and 45 degrees; the same on every
// mesh size (tested). The quadratic part stays isotropic. A direction-exact stiffening would
// need a per-triangle curvature tensor (a wider stencil), not a hinge term.

#include <vector>

#include "twin/model/bending_calibration.h"
#include "twin/model/rest_curvature.h"

namespace twin {

// d_e (m) per hinge, for the hinges of `map` with the stiffness calibration `calibration`.
std::vector<double> stiffening_lengths(const HingeCurvatureMap& map,
                                       const BendingCalibration& calibration);

// Hinge angle per unit curvature (m, signed) of hinge e for a cylinder whose curvature acts
// along the material direction at `angle_rad` from u, in the small-curvature limit.
double cylinder_angle_per_curvature(const HingeCurvatureMap& map, int e, double angle_rad);

}  // namespace twin
