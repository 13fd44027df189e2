#pragma once
// The scanner lab's "real" sheet as the reference shell (sim_hw/spline_shell,
// docs/reference_sheet.md): the trial's clamp path followed on the coarsest spline level, each
// stage carried up `levels` bisections (exact knot insertion, solved again: falls included, so
// every level is on the path's branch), the markers and normals read on the finest. Each
// stage's truth error comes from the levels it has: the two finest levels' change, and with two
// levels or more above level 0 the observed order and the finest level's estimated error (what
// `reference_refinement` prints for the trial, with its labels and eigenvalues).

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
