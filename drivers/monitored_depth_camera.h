#pragma once
// The checks every depth-camera back-end gets, as a decorator around any DepthCamera, so real,
// simulated and replayed cameras are judged by the same rules:
//  - corrupt frames (image size vs intrinsics, all-zero depth, non-finite intrinsics or
//    extrinsics) -> ReadStatus::kCorrupt, the frame must not be used;
//  - frozen stream: config.frozen_after_frames identical depth images in a row -> kFrozen
//    (default 3: flagged on the second repeat, i.e. within 3 frames of the freeze);
//  - stale timestamps: the device timestamp does not advance, or the host-minus-device clock
//    offset grew by more than config.stale_after over its running minimum (the frame waited
//    too long somewhere) -> kStale;
//  - dropped frames: gaps in the device sequence counter (counted, the frame is still kFrame).
// health() is the wrapped camera's (state, timeouts, reopen counts) with the monitor's frame
// counts, and Degraded with a message while the latest read was flagged or timed out.
// Choice: the registry's make_depth_camera() returns bare back-ends (tests and back-ends stay
// plain); the cell and tools open cameras with make_monitored_depth_camera(). Never throws on
// read().

#include <cstdint>
#include <memory>
#include <string>

#include "drivers/depth_camera.h"

namespace drivers {

class MonitoredDepthCamera : public DepthCamera {
 public:
  explicit MonitoredDepthCamera(std::unique_ptr<DepthCamera> inner);

  DriverResult configure(const CameraConfig& config) override;
  DriverResult activate() override;
  ReadStatus read(DepthFrame& frame) override;
  CameraHealth health() const override;
  DriverResult deactivate() override;

  std::uint64_t corrupt_frames() const { return corrupt_; }  // CameraHealth has no field for it
  DepthCamera& inner() { return *inner_; }

 private:
  void reset_stream_baselines();
  ReadStatus check(DepthFrame& frame, ReadStatus inner_status);
  void degrade(std::string why);

  std::unique_ptr<DepthCamera> inner_;
  CameraConfig config_;
  // Counts over the camera's life.
  std::uint64_t frames_ = 0, dropped_ = 0, stale_ = 0, frozen_ = 0, corrupt_ = 0;
  std::int64_t last_frame_host_time_us_ = 0;
  // Stream baselines, reset at activation and after a loss (a reopened device restarts them).
  bool have_previous_ = false;
  std::uint64_t last_sequence_ = 0;
  std::int64_t last_device_time_us_ = 0;
  std::int64_t offset_baseline_us_ = 0;  // running minimum of host - device time
  std::uint64_t last_hash_ = 0;
  int identical_run_ = 0;  // depth images in a row with the same content
  bool degraded_ = false;
  std::string message_;
};

// make_depth_camera(backend) wrapped in a MonitoredDepthCamera.
std::unique_ptr<DepthCamera> make_monitored_depth_camera(const std::string& backend);

}  // namespace drivers
