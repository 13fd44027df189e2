#pragma once
// The hidden effect of a blind trial set (issue 6): which physics beyond the paper's model the
// scanner lab's sheet has, and how strong, drawn from a seed. The analysing side (twin diagnose)
// never sees the seed, the choice or the magnitudes; only the trial files.
//
// Effects (names as in twin/model/model_effects.h and the diagnose verdict), equally likely:
//   none                     the specimen's own material
//   orthotropic_stiffness    warp/weft bending ratio 0.3-0.6 or 1.7-2.5 (hinge bending on the
//                            twin's coarse meshes represents up to about 2.6), tensile 0.5-2
//                            (geometric means kept, so the sheet is not just stiffer)
//   rest_curvature           roll set of radius 0.3-1.5 m along a random direction, either side
//   nonlinear_bending        beta with beta kappa^2 = 0.5-3 at the trial's typical curvature
//   marker_mass              0.5-2 g per marker (quarter-inch raised markers)
//   viscoelastic_relaxation  fraction 0.3-0.6, time constant 60-600 s
//   clamp_grip               the jaws grip 2-6 cm further out than the trial file's grip
//                            radii say, with strength 0.3-1.5 (twin/model/clamp_grip_term.h). The markers
//                            hidden stay those within the lab's jaw radius: which markers a
//                            trial hides must not give the effect away. Rigid jaws of a wider radius were
//                            tried first: on the 300-triangle reference mesh they grip whole
//                            9 cm triangles or nothing, a change no smooth model follows.
//   clamp_slip               the ply slips in the jaws by 0.1-1 mm per newton of pull along the
//                            jaw faces (twin/model/clamp_slip_term.h)
//   outside_library          the ply was folded in four once: two perpendicular creases
//                            (sim_hw/crease.h) through a point near the middle, 40-80 deg each
// The ranges are the lab's idea of realistic, not the analysis's: diagnose must not rely on them.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "sim_hw/crease.h"
#include "sim_hw/lab_materials.h"
#include "twin/model/material.h"

namespace sim_hw {

// The nine names above, in a fixed order.
const std::vector<std::string>& blind_effect_names();

struct HiddenEffect {
  std::string effect;       // one of blind_effect_names()
  std::string description;  // one line for people
  // What was drawn, in SI units (names end in their unit; twin parameter names where one exists).
  std::vector<std::pair<std::string, double>> parameters;
  twin::Material truth;          // the specimen's material carrying the effect (twin's effects)
  std::vector<Crease> creases;  // outside_library only: applied to the reference sheet
};

// The effect the seed picks (uniformly over blind_effect_names()).
std::string effect_for_seed(std::uint64_t seed);

// Draws the effect's magnitude from the seed. `effect` is effect_for_seed(seed) unless a test
// forces one (throws std::invalid_argument for a name not in blind_effect_names()).
// `typical_curvature_1_m` is called only for nonlinear_bending: the curvature (1/m) the specimen
// typically reaches in the lab's trials without the effect.
HiddenEffect draw_hidden_effect(std::uint64_t seed, const std::string& effect, const LabSpecimen& specimen,
                                const std::function<double()>& typical_curvature_1_m);

// Derived seeds: independent streams from one seed (splitmix64), so that e.g. the clamp
// protocol of a trial does not depend on which effect was drawn.
std::uint64_t derived_seed(std::uint64_t seed, std::uint64_t stream);

}  // namespace sim_hw
