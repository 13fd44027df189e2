#pragma once
// Simulates a trial's stages in order, as the clamps really moved (a hanging sheet has several
// equilibria; the path selects one). The sheet starts flat and level, turned about the vertical
// and shifted so that the clamps' material points best fit their stage-1 positions, at the
// stage-1 clamps' mean height; every stage is then reached by quasi-static continuation from
// the one before. Used by identification (thousands of times, on a coarse twin mesh) and by
// the scanner lab (once, on a fine reference mesh).

#include <string>
#include <vector>

#include "twin/quasi_static.h"
#include "twin/trial.h"

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
TrialSimulation simulate_stages(const ShellModel& model, const ClampSet& clamps,
                                const std::vector<TrialStage>& stages,
                                const ContinuationOptions& options = {});

}  // namespace twin
