#pragma once
// Replays one camera of a recorded session (camera_session.h) as a DepthCamera, back-end
// "replay". CameraConfig::uri = "<session dir>#<camera name>[?option&option...]" with options
//   pace=recorded  (default) deliver frames with the recorded host-time spacing
//   pace=fast      deliver the next frame at once on every read (benchmarks, CI)
//   loop=1         start again at the first frame after the last (default: end = kTimeout)
//   rebase=1       host_time_us = replay start (steady clock) + recorded offset, so that live
//                  staleness checks work; default: the recorded host_time_us, unchanged
//   live=1         as a live camera: with pace=recorded a read that comes late gets the newest
//                  frame already due (skipped ones count as dropped), and with loop=1 each pass
//                  continues the sequence and device time of the last (frame monitors see one
//                  stream); default: every frame in turn however late, each pass as recorded
// Frames carry the recorded sequence, timestamps, intrinsics and images bit for bit;
// CameraConfig::name renames the camera if set, and a non-identity CameraConfig::camera_to_cell
// replaces the recorded extrinsics (a re-calibrated cell). configure() checks session.json, the
// index and that every frame file exists, and fails naming the file and field or line; a frame
// file that turns out corrupt at read() is skipped with health().message naming it.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "drivers/camera_session.h"
#include "drivers/depth_camera.h"

namespace drivers {

class ReplayDepthCamera : public DepthCamera {
 public:
  DriverResult configure(const CameraConfig& config) override;
  DriverResult activate() override;
  ReadStatus read(DepthFrame& frame) override;
  CameraHealth health() const override { return health_; }
  DriverResult deactivate() override;

  std::size_t recorded_frames() const { return index_.size(); }

 private:
  bool load(std::size_t i, DepthFrame& frame);

  CameraConfig config_;
  SessionCamera camera_;
  std::filesystem::path folder_;
  std::vector<SessionIndexEntry> index_;
  bool fast_ = false, loop_ = false, rebase_ = false, live_ = false;
  std::uint64_t pass_sequence_ = 0;   // live=1: added to the recorded sequence (earlier passes)
  std::int64_t pass_device_us_ = 0;   // live=1: added to the recorded device time (us)
  std::int64_t pass_host_us_ = 0;     // one loop pass on the host clock (us)
  std::int64_t pass_device_us() const;  // one loop pass on the device clock (us)
  bool configured_ = false, active_ = false;
  std::size_t next_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::int64_t start_us_ = 0, offset_us_ = 0;  // offset_us_: recorded host time at start_ (loops)
  bool have_last_ = false;
  std::uint64_t last_sequence_ = 0;
  CameraHealth health_;
};

}  // namespace drivers
