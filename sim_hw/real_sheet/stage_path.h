#pragma once
// The scanner lab's handling of the independent sheet through a trial's stages, as the clamps
// really moved. The sheet lies flat and level (turned about the vertical and shifted so its
// clamps' material points best fit their stage-1 positions, at their mean height); the jaws
// close on it there and it is let go into gravity (an overdamped fall, the damped solver's
// pseudo-time); the jaws then travel to each stage's poses in increments, each solved to
// equilibrium; a jaw that opens lets the sheet fall again. With creep, moves are made on the
// fresh material and the stage is then solved again at its age.

#include <string>
#include <vector>

#include "sim_hw/real_sheet/equilibrium_solver.h"
#include "sim_hw/real_sheet/sheet_model.h"
#include "twin/model/clamp.h"
#include "twin/trials/trial.h"

namespace sim_hw::real_sheet {

struct PathStage {
  std::vector<twin::ClampPose> poses;  // one per clamp (position of its material point; engaged)
  double age_s = std::numeric_limits<double>::quiet_NaN();  // since the clamps last moved
};

// A trial's stages as the path takes them: the poses, and the age since the clamps last moved
// where the trial says both times (NaN otherwise).
std::vector<PathStage> path_stages(const std::vector<twin::TrialStage>& stages);

struct PathOptions {
  JawKind jaws = JawKind::kRigid;
  JawPadOptions pad;  // radius from each clamp; extension and slip from the material
  double increment_m = 0.02;       // largest jaw travel per solved increment
  EquilibriumOptions equilibrium;  // per increment
};

struct PathResult {
  std::vector<VecX> stages;  // equilibrium positions per stage reached
  std::vector<std::vector<JawHold>> holds;  // per stage, the jaws holding (pivots' turns included)
  std::vector<EquilibriumReport> reports;
  int increments = 0, iterations = 0, factorizations = 0;
  std::string failure;  // "stage 3: ..." when a stage was not reached
  bool usable() const { return failure.empty(); }
};

PathResult simulate_path(SheetModel& model, const std::vector<twin::ClampSpec>& clamps,
                         const std::vector<PathStage>& stages, const PathOptions& options = {});

// The stage's equilibrium on another grid of the same sheet: the shape `x` of `from` carried over
// by cubic interpolation in material coordinates (Grid::smooth_position) (the jaws' pads rebuilt on the new grid, at
// the same poses) and solved there to equilibrium. The branch is the one `x` is on: this is how
// the lab puts a path followed on a coarse grid onto the fine grid it reports, and how the
// refinement study compares grids on one branch. `to` must be at the age the stage was solved
// at. Throws std::runtime_error when the solve does not converge.
VecX carry_to_grid(const SheetModel& from, const VecX& x, const std::vector<JawHold>& holds, const SheetModel& to,
                   const PathOptions& options = {}, EquilibriumReport* report = nullptr);

// The level placement of the flat sheet for stage-1 clamp positions: rotation about z and shift
// fitting the engaged clamps' material points by least squares, at their mean height. Returns
// the rotation (3 x 3) and the world position of material point (0, 0).
struct LevelPlacement {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 origin_m = Vec3::Zero();
  Vec3 to_world(const Vec2& uv) const { return origin_m + rotation * Vec3(uv.x(), uv.y(), 0.0); }
};
LevelPlacement level_placement(const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::ClampPose>& poses);

}  // namespace sim_hw::real_sheet
