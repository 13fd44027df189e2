#pragma once
// The checks every depth back-end applies to the frames it delivers, so all report the same
// way: gaps in the device's frame counter (dropped frames), a device clock that does not advance
// (stale frame), and the same depth image again and again (frozen stream).

#include <cstdint>
#include <vector>

#include "drivers/depth_camera.h"

namespace drivers {

class StreamChecks {
 public:
  void reset() { *this = StreamChecks{}; }

  // Counts `frame` in `health` (frames, dropped, stale, frozen, last frame time, state and
  // message) and says how read() should report it: kFrame, kStale or kFrozen. The stream is
  // frozen once `frozen_after_frames` images in a row are identical.
  ReadStatus check(const DepthFrame& frame, int frozen_after_frames, CameraHealth& health);

  std::uint64_t last_sequence() const { return last_sequence_; }

 private:
  std::uint64_t last_sequence_ = 0;  // 0 = no frame yet
  std::int64_t last_device_time_us_ = -1;
  std::vector<std::uint16_t> last_depth_;
  int identical_run_ = 0;  // frames identical to their predecessor, in a row
};

}  // namespace drivers
