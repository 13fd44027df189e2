#include "drivers/stream_checks.h"

#include <algorithm>

#include <fmt/format.h>

namespace drivers {

ReadStatus StreamChecks::check(const DepthFrame& frame, int frozen_after_frames, CameraHealth& health) {
  if (last_sequence_ != 0 && frame.sequence > last_sequence_ + 1) {
    health.dropped += frame.sequence - last_sequence_ - 1;
  }
  const bool stale = last_device_time_us_ >= 0 && frame.device_time_us <= last_device_time_us_;
  identical_run_ = (!last_depth_.empty() && last_depth_ == frame.depth_mm) ? identical_run_ + 1 : 0;
  const bool frozen = identical_run_ + 1 >= frozen_after_frames;
  last_sequence_ = frame.sequence;
  last_device_time_us_ = std::max(last_device_time_us_, frame.device_time_us);
  last_depth_ = frame.depth_mm;
  ++health.frames;
  health.last_frame_host_time_us = frame.host_time_us;
  if (stale) {
    ++health.stale;
    health.state = CameraState::kDegraded;
    health.message = fmt::format("stale frame {}: device time {} us did not advance", frame.sequence,
                                 frame.device_time_us);
    return ReadStatus::kStale;
  }
  if (frozen) {
    ++health.frozen;
    health.state = CameraState::kDegraded;
    health.message = fmt::format("frozen stream: {} identical depth images", identical_run_ + 1);
    return ReadStatus::kFrozen;
  }
  health.state = CameraState::kActive;
  health.message.clear();
  return ReadStatus::kFrame;
}

}  // namespace drivers
