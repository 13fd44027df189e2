#pragma once
// The scanner lab's "real" sheet as the reference shell (sim_hw/spline_shell,
// docs/reference_sheet.md): the trial's clamp path followed on the coarsest spline level, each
// stage carried up `levels` bisections (a stage that lets a jaw go falls again on each level),
// the markers and normals read on the finest. How far that level is from converged is what
// `reference_refinement` measures for the trial.

#include <vector>

#include "sim_hw/crease.h"
#include "sim_hw/lab_reference.h"
#include "twin/model/material.h"
#include "twin/trials/trial.h"

namespace sim_hw {

// Throws std::runtime_error naming the level and stage that did not settle, std::invalid_argument
// for jaws the shell does not have (pivot).
ReferenceStages shell_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                const std::vector<Crease>& creases, double width_m, double height_m,
                                const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::TrialStage>& stages,
                                const std::vector<twin::Vec2>& marker_uv_m);

}  // namespace sim_hw
