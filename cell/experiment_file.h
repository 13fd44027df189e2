#pragma once
// The experiment file (JSON): the paper's section 5.3 experiment as a list of states. After
// READY the cell applies each state's actions in order, lets the sheet settle, then averages the
// errors over the last window of cycles:
//   {"settle_s": 6.0,                         (default settling time per state, s)
//    "window_s": 1.0,                         (optional: averaging window at the end, s)
//    "states": [{"name": "four grasps", "actions": [],
//                "settle_s": 4.0},            (optional: this state's settling time, s)
//               {"name": "MANUAL released", "actions": [{"release": "MANUAL"}]},
//               {"name": "CENTER raised",
//                "actions": [{"move": "CENTER", "to_m": [0.26, 0.30, 1.15]}]}]}
// "release" opens the gripper (the twin lets go when its status stops holding); "move" moves the
// gripper's jaw target in a straight line to to_m (cell frame, m) at the cell's move speed. The
// settling time counts from when the state's actions are done. Errors throw std::invalid_argument
// naming the file and field.
#include <string>
#include <vector>

#include "twin/base/types.h"

namespace cell {

struct ExperimentAction {
  enum class Kind { kRelease, kMove };
  Kind kind = Kind::kRelease;
  std::string gripper;
  twin::Vec3 to_m = twin::Vec3::Zero();  // kMove only
};

struct ExperimentState {
  std::string name;
  std::vector<ExperimentAction> actions;
  double settle_s = 6.0;
};

struct Experiment {
  std::vector<ExperimentState> states;
  double window_s = 1.0;
};

Experiment read_experiment(const std::string& path);

}  // namespace cell
