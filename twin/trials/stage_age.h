#pragma once
// How long a trial stage's load had been on when the stage was scanned: the age that
// viscoelastic relaxation (model_effects.h) depends on. From the stage fields (docs/file_formats.md,
// "Trial directory"):
//   time_s             when the stage was scanned (s, any common origin);
//   clamps_moved_at_s  when the clamps reached this stage's poses (s, same clock).
// age = time_s - clamps_moved_at_s. When clamps_moved_at_s is absent it defaults to
//   - the previous stage's clamps_moved_at (or its default) if this stage's clamp poses are
//     exactly the previous stage's (nothing moved: the sheet kept relaxing);
//   - otherwise the previous stage's time_s: the clamps moved right after that scan, so the
//     age is the time between the two scans (an upper bound when the move took a while);
//   - unknown (NaN) for the first stage, or when a time it needs is absent.
// An unknown age counts as fully relaxed (ModelEffects::relaxation_factor). Without relaxation
// in the material none of this matters.

#include <vector>

#include "twin/trials/trial.h"

namespace twin {

// One age (s, >= 0, or NaN when unknown) per stage, in order.
std::vector<double> stage_load_ages_s(const std::vector<TrialStage>& stages);

// The clamp poses of two stages are the same (engaged flags and positions exactly equal).
bool same_clamp_poses(const TrialStage& a, const TrialStage& b);

// `stage` scans again the sheet `previous` scanned, nothing moved between: the same clamp poses,
// and no new moment at which the clamps stopped (clamps_moved_at_s absent, or the previous one's).
bool scans_same_pose(const TrialStage& previous, const TrialStage& stage);

}  // namespace twin
