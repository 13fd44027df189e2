#pragma once
// The cell's watchdog, as a pure function of what the cycle measured, so every rule is testable
// on its own and the cell recovers by itself the cycle a cause clears:
//   fresh cameras < min_cameras, a twin failure, an arm status older than the timeout, or (on
//       the fake world's clock) a simulation clock that fell silent -> SAFE_HOLD (no robot or gripper commands), the reason names every cause;
//   otherwise fewer fresh cameras than configured, or cameras that disagree where they see the
//       same part of the sheet (calibration check) -> DEGRADED naming them;
//   otherwise RUNNING.
#include <cstdint>
#include <string>
#include <vector>

namespace cell {

enum class CellState : std::int8_t {  // same values as prepreg_lcm::cell_state_t::STATE_*
  kStarting = 0,
  kReady = 1,
  kRunning = 2,
  kDegraded = 3,
  kSafeHold = 4,
  kFailed = 5,
  kStopped = 6,
};
const char* to_string(CellState state);

struct WatchdogInputs {
  int cameras = 0;
  int min_cameras = 1;
  std::vector<std::string> lost_cameras;  // not fresh, each "name (why)"
  std::string calibration_problem;        // "" while the cameras agree
  bool twin_ok = true;
  std::string twin_problem;
  std::vector<std::string> stale_arms;    // no IIWA_STATUS within the timeout
  double robot_status_timeout_ms = 0;
  std::string clock_problem;  // "" while the process's clock runs (always on the wall)
};

struct WatchdogVerdict {
  CellState state = CellState::kRunning;
  std::string reason;  // "" when RUNNING
  bool cameras_ok = true, twin_ok = true, robots_ok = true;
};

WatchdogVerdict judge(const WatchdogInputs& in);

// True in the states where the cell may send robot and gripper commands.
inline bool may_command(CellState s) { return s == CellState::kRunning || s == CellState::kDegraded; }

}  // namespace cell
