#pragma once
// A cell run's settled states from its lcm-logger log (issue 35: the offline path cell log ->
// trial -> twin identify / twin diagnose, for a run that wrote no observed trial itself).
//
// The log holds what the cell saw and did: SHEET_OBSERVED (the tracked surface per cycle, with
// its seen flags), IIWA_STATUS_<ARM> (measured joints: the jaws by forward kinematics, as the
// running cell computes them), GRIPPER_STATUS_<G> (holding or not), and on fake hardware
// SIM_SHEET_TRUTH. Replayed in log order through the same settled-state detector as the live
// cell (cell/learning/settled_state.h), on the log's clock. A gripper without an arm is where
// the plan holds it; one with no status yet counts as holding.
#include <cstdint>
#include <string>
#include <vector>

#include "cell/cell_config.h"
#include "cell/learning/settled_state.h"
#include "twin/trials/grasp_plan.h"

namespace cell {

struct LoggedStates {
  std::vector<learning::SettledObservation> states;  // as the store keeps them (max_states)
  std::int64_t observed_sheets = 0, arm_statuses = 0, gripper_statuses = 0, truths = 0;
  std::int64_t other_mesh = 0;    // observed sheets skipped: not the config's mesh
  std::int64_t undecodable = 0;   // events of those channels that did not decode
};

// Throws std::runtime_error naming the file when it cannot be read or is not an LCM log.
LoggedStates settled_states_from_log(const std::string& log_path, const CellConfig& config,
                                     const twin::GraspPlan& plan);

}  // namespace cell
