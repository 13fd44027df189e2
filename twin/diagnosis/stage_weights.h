#pragma once
// Stage weights for a robust refit. A hanging sheet has several equilibria, and a material
// near the truth can leave one stage on a neighbouring fold: that stage's misfit is then
// centimetres where the others are at the noise, and least squares lets that single stage
// pull the fit off the material every other stage agrees on (blind set 4001: one training
// stage at 20x the median stage misfit carried the refit into a region where a held-out
// stage's scanned fold does not exist; with that stage left out the refit reached the hidden
// truth). Iteratively reweighted least squares over stages bounds such a stage's pull: its
// weight makes its weighted misfit that of a stage at kOutlierRatio times the median.
//
// The weights only choose where the refit searches. refit.cc polishes the result without
// weights and keeps it only when, simulated fresh, it fits all training stages better than
// the plain least-squares refit, so every score and verdict stays a least-squares one, and
// a missing effect that shows in a few stages (the outside-library sets) is still judged on
// every stage.

#include <string>
#include <vector>

#include "twin/trials/identification.h"

namespace twin::diagnosis {

// A stage whose RMS residual exceeds this multiple of the median stage's is down-weighted.
// Over the blind sets' refits (sets of the twin's own truth) the
// largest stage over the median was at most 1.8x where the refit was right, and 5.8-20x where
// one or two stages sat on another fold or carried physics outside the library.
inline constexpr double kOutlierStageRatio = 3.0;

struct OutlierStage {
  std::string trial, stage;  // trial directory name, stage id
  double rms_m = 0.0;        // the stage's RMS residual per coordinate
  double ratio = 0.0;        // rms_m over the median stage's
  double weight = 1.0;       // (kOutlierStageRatio / ratio)^2
};

struct StageWeights {
  std::vector<std::vector<double>> weights;  // per trial, per stage (IdentificationProblem)
  std::vector<OutlierStage> outliers;        // the stages given a weight below 1
  double median_rms_m = 0.0;
};

// From an evaluation's per-trial fits (their raw residuals and residual blocks);
// `trial_names` per training trial. Stages without residuals keep weight 1 and do not count
// towards the median. No outliers (and all weights 1) with fewer than three scored stages.
StageWeights outlier_stage_weights(const IdentificationProblem::Evaluation& evaluation,
                                   const std::vector<std::string>& trial_names,
                                   double ratio = kOutlierStageRatio);

}  // namespace twin::diagnosis
