#include "drivers/depth_camera.h"

#include "common/process_clock.h"

namespace drivers {

std::int64_t host_clock_us() { return prepreg::process_steady_us(); }

const char* to_string(ReadStatus status) {
  switch (status) {
    case ReadStatus::kFrame: return "frame";
    case ReadStatus::kTimeout: return "timeout";
    case ReadStatus::kStale: return "stale";
    case ReadStatus::kFrozen: return "frozen";
    case ReadStatus::kLost: return "lost";
    case ReadStatus::kNotActive: return "not active";
    case ReadStatus::kCorrupt: return "corrupt";
  }
  return "?";
}

const char* to_string(CameraState state) {
  switch (state) {
    case CameraState::kUnconfigured: return "unconfigured";
    case CameraState::kConfigured: return "configured";
    case CameraState::kActive: return "active";
    case CameraState::kDegraded: return "degraded";
    case CameraState::kLost: return "lost";
  }
  return "?";
}

}  // namespace drivers
