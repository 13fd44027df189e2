#pragma once
// What a stage's levels say about the finest level's own error: the markers' change between
// successive levels (each span bisected, ratio 2), compared only where the two levels are on one
// branch (branch_label.h); from the two finest changes on one branch the observed order
// p = log2(e_{L-2,L-1} / e_{L-1,L}) and Richardson's estimate of the finest level's error
// e_{L-1,L} / (2^p - 1) (Roache's GCI is 1.25 times it). Mean changes give the order: a max
// sits at one marker, which may move from level to level. An order below 0.2 gives no estimate
// (the levels are not in the asymptotic range, or the change is at rounding).

#include <optional>
#include <string>
#include <vector>

#include "sim_hw/spline_shell/branch_label.h"

namespace sim_hw::spline_shell {

struct LevelChange {
  double mean_m = 0, max_m = 0;  // over the counted markers
  int max_marker = -1;            // the marker that moved most (say where the change is)
  bool same_branch = true;
  std::string why;  // the fold that differs, when not one branch
};

struct BranchMatch {
  double tolerance_m = 0.02;
  double significant_fold_m2 = 1e-3;
};

struct StageRefinement {
  std::vector<LevelChange> changes;  // level l against l + 1
  std::optional<double> order;           // observed, from the two finest changes
  std::optional<double> finest_error_m;  // Richardson, of the mean
  // Why there is no order: "one change only", "the two finest comparisons are not on one branch",
  // "order below 0.2" (empty when there is one).
  std::string no_order;
  bool estimated() const { return finest_error_m.has_value(); }
  // The finest comparison (levels L-1, L): what the truth's error is at most of the order of.
  const LevelChange& finest() const { return changes.back(); }
};

// markers[level][marker] of one stage, labels[level]; counted[marker]: the markers that enter
// the means (a closed jaw's hold the same at every level). At least two levels, equal counts.
// Throws std::invalid_argument otherwise.
StageRefinement stage_refinement(const std::vector<std::vector<Vec3>>& markers, const std::vector<BranchLabel>& labels,
                                 const std::vector<bool>& counted, const BranchMatch& match = {});

// "0->1 1.703 / 8.911 mm" or "1->2 BRANCH FLIP (why; markers 4.1 / 20.0 mm)": mean / max.
std::string change_text(int level, const LevelChange& change);

// "order 2.21, finest error 0.101 mm (GCI 0.126)" or "no order: <why>".
std::string estimate_text(const StageRefinement& r);

// Every change, then the estimate where there are two changes or more:
// "0->1 1.703 / 8.911 mm  1->2 0.367 / 1.707 mm  | order 2.21, ...".
std::string summary_text(const StageRefinement& r);

}  // namespace sim_hw::spline_shell
