#include "cell/watchdog.h"

#include <fmt/format.h>

namespace cell {

const char* to_string(CellState state) {
  switch (state) {
    case CellState::kStarting: return "STARTING";
    case CellState::kReady: return "READY";
    case CellState::kRunning: return "RUNNING";
    case CellState::kDegraded: return "DEGRADED";
    case CellState::kSafeHold: return "SAFE_HOLD";
    case CellState::kFailed: return "FAILED";
    case CellState::kStopped: return "STOPPED";
  }
  return "?";
}

namespace {
std::string join(const std::vector<std::string>& items, const char* sep = ", ") {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : sep) + s;
  return out;
}
}  // namespace

WatchdogVerdict judge(const WatchdogInputs& in) {
  WatchdogVerdict v;
  const int fresh = in.cameras - static_cast<int>(in.lost_cameras.size());
  v.cameras_ok = fresh >= in.min_cameras;
  v.twin_ok = in.twin_ok;
  v.robots_ok = in.stale_arms.empty();
  std::vector<std::string> causes;
  if (!v.cameras_ok) {
    causes.push_back(fmt::format("{} of {} cameras fresh (minimum {}): lost {}", fresh, in.cameras,
                                 in.min_cameras, join(in.lost_cameras)));
  }
  if (!v.twin_ok) causes.push_back("twin failure: " + in.twin_problem);
  if (!in.clock_problem.empty()) causes.push_back(in.clock_problem);
  if (!v.robots_ok) {
    causes.push_back(fmt::format("no arm status within {:.0f} ms from {}", in.robot_status_timeout_ms,
                                 join(in.stale_arms)));
  }
  if (!causes.empty()) {
    v.state = CellState::kSafeHold;
    v.reason = join(causes, "; ");
  } else if (!in.lost_cameras.empty() || !in.calibration_problem.empty()) {
    v.state = CellState::kDegraded;
    std::vector<std::string> why;
    if (!in.lost_cameras.empty()) {
      why.push_back(fmt::format("{} of {} cameras fresh: lost {}", fresh, in.cameras, join(in.lost_cameras)));
    }
    if (!in.calibration_problem.empty()) why.push_back(in.calibration_problem);
    v.reason = join(why, "; ");
  }
  return v;
}

}  // namespace cell
