#include "twin/trials/stage_age.h"

#include <algorithm>
#include <limits>

namespace twin {

bool same_clamp_poses(const TrialStage& a, const TrialStage& b) {
  if (a.poses.size() != b.poses.size()) return false;
  for (std::size_t i = 0; i < a.poses.size(); ++i) {
    const ClampPose &p = a.poses[i], &q = b.poses[i];
    if (p.engaged != q.engaged) return false;
    if (p.engaged && p.position_m != q.position_m) return false;
  }
  return true;
}

bool scans_same_pose(const TrialStage& previous, const TrialStage& stage) {
  if (!same_clamp_poses(previous, stage)) return false;
  return !stage.clamps_moved_at_s || previous.clamps_moved_at_s == stage.clamps_moved_at_s;
}

std::vector<double> stage_load_ages_s(const std::vector<TrialStage>& stages) {
  constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> ages;
  double moved_at_s = kUnknown;  // when the clamps last moved, as of the stage being read
  for (std::size_t s = 0; s < stages.size(); ++s) {
    const TrialStage& stage = stages[s];
    if (stage.clamps_moved_at_s) {
      moved_at_s = *stage.clamps_moved_at_s;
    } else if (s == 0) {
      moved_at_s = kUnknown;
    } else if (!same_clamp_poses(stage, stages[s - 1])) {
      moved_at_s = stages[s - 1].time_s.value_or(kUnknown);
    }  // else: nothing moved since the previous stage; its moment stands
    // NaN propagates: an unknown time makes an unknown age. Clocks that disagree by rounding
    // must not make a negative age.
    ages.push_back(stage.time_s ? std::max(*stage.time_s - moved_at_s, 0.0) : kUnknown);
  }
  return ages;
}

}  // namespace twin
