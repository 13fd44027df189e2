#pragma once
// Simulates a trial's stages in order, as the clamps really moved (a hanging sheet has several
// equilibria; the path selects one). The sheet starts flat and level, turned about the vertical
// and shifted so that the clamps' material points best fit their stage-1 positions, at the
// stage-1 clamps' mean height; every stage is then reached by quasi-static continuation from
// the one before. Used by identification (thousands of times, on a coarse twin mesh) and by
// the scanner lab (once, on a fine reference mesh).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "twin/solvers/quasi_static.h"
#include "twin/trials/trial.h"

namespace twin {

struct StageSimulation {
  std::string id;
  ContinuationReport report;
  VecX x;  // equilibrium positions (3n, m); empty if the stage failed or was not reached
};

struct TrialSimulation {
  std::vector<StageSimulation> stages;  // up to and including the first failed stage
  bool usable() const;                  // every stage reached an equilibrium
  std::string failure;                  // "stage 3: ..." when not usable
};

// The level placement (rotation about z, shift) that best fits the clamps' material points to
// their engaged positions (least squares), at their mean height. Throws std::invalid_argument
// when no clamp is engaged.
SheetPlacement fit_level_placement(const std::vector<ClampSpec>& clamps,
                                   const std::vector<ClampPose>& poses);

// Runs every stage of `stages` (clamps in ClampSet order). Stops at the first stage that fails.
// Load ages (stage_age.h), for a material with viscoelastic relaxation: the clamps travel with
// the model at age 0 (a move takes seconds, the relaxation minutes: the sheet answers a move
// with its unrelaxed stiffness, and the quasi-elastic model keeps no memory of earlier loads),
// then the stage's equilibrium is solved again at the stage's age with the clamps where they
// stopped (the sheet relaxing until the scan). Without relaxation the age changes nothing and
// that second solve is skipped. The model is left at the last simulated stage's age.
// `on_stage`, when given, is called with each stage's index and equilibrium as soon as it is
// reached (so a caller can start work on it while later stages are simulated).
using StageReached = std::function<void(std::size_t stage, const VecX& x)>;
TrialSimulation simulate_stages(ShellModel& model, const ClampSet& clamps,
                                const std::vector<TrialStage>& stages,
                                const ContinuationOptions& options = {},
                                const StageReached& on_stage = nullptr);

}  // namespace twin
