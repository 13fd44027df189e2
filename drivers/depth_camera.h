#pragma once
// The one depth-camera interface of the cell (issue 4). Real back-ends (V4L2, OpenNI2) live in
// drivers/, simulated and replayed ones elsewhere; all are chosen at start-up from a
// CameraConfig by its `backend` name (see camera_registry.h). Nothing above this interface asks
// which kind of camera it has.
//
// Lifecycle, as ros2_control's hardware interfaces: configure (check the config, open the
// device), activate (start streaming), then cyclic read(), deactivate. The cyclic path never
// throws: read() returns a status and health() says why a camera is unwell.
//
// Frames: a D415 has a depth sensor (stereo IR pair; depth in the left IR camera's frame) and a
// separate colour sensor. Depth is uint16 millimetres (0 = no measurement), row-major. Colour is
// RGB8, row-major, in the colour camera's own image; `depth_to_color` maps points from the depth
// camera frame to the colour camera frame so a tracker can look up each depth pixel's colour.
// Camera frames follow the pinhole convention: x right, y down, z forward (m).

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace drivers {

// Pinhole intrinsics of one image stream (pixels), with Brown-Conrady distortion (zero for a
// D415's rectified depth stream).
struct Intrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};

// One stream mode: resolution and frame rate (frames/s).
struct StreamMode {
  int width = 0, height = 0;
  int fps = 0;
};

struct CameraConfig {
  std::string name;            // unique within the cell, e.g. "cam_left"
  std::string backend;         // "v4l2", "openni2", "replay", "simulated", ...
  std::string uri;             // device path(s), OpenNI URI, recording directory, ... (backend's)
  std::string serial;          // expected serial number; empty = do not check
  StreamMode depth_mode{848, 480, 30};
  StreamMode color_mode{848, 480, 30};
  Intrinsics depth_intrinsics;  // from the camera's calibration (V4L2 cannot read it)
  Intrinsics color_intrinsics;
  Eigen::Isometry3d depth_to_color = Eigen::Isometry3d::Identity();  // m
  Eigen::Isometry3d camera_to_cell = Eigen::Isometry3d::Identity();  // depth frame -> cell, m
  double depth_unit_mm = 1.0;   // millimetres per raw depth count (D415 default 1.0)
  std::chrono::milliseconds read_timeout{200};  // read() waits at most this long
  std::chrono::milliseconds stale_after{500};   // frame older than this (host clock) = stale
  // Identical depth images in a row = frozen stream. 3 flags a freeze on its second repeated
  // frame (issue 4: within 3 frames); a live D415's depth noise never repeats an image exactly.
  int frozen_after_frames = 3;
};

struct DepthFrame {
  std::string camera;          // CameraConfig::name
  std::uint64_t sequence = 0;  // device frame counter (gaps = dropped frames)
  std::int64_t device_time_us = 0;  // sensor timestamp (device clock)
  std::int64_t host_time_us = 0;    // when the host received it (host_clock_us())
  Intrinsics depth_intrinsics;
  std::vector<std::uint16_t> depth_mm;  // width*height, row-major, 0 = invalid
  Intrinsics color_intrinsics;          // width 0 when the frame has no colour
  std::vector<std::uint8_t> rgb;        // width*height*3, row-major
  Eigen::Isometry3d depth_to_color = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_to_cell = Eigen::Isometry3d::Identity();
};

// Result of a lifecycle call: ok, or a message naming what failed (device, field, errno text).
struct DriverResult {
  bool ok = true;
  std::string message;
  static DriverResult success() { return {}; }
  static DriverResult failure(std::string why) { return {false, std::move(why)}; }
};

enum class ReadStatus {
  kFrame,      // a new frame was written to the output
  kTimeout,    // nothing within read_timeout; try again
  kStale,      // a frame arrived but its timestamp is too old (returned, flagged)
  kFrozen,     // the stream repeats the same image (returned, flagged)
  kLost,       // the device went away; the driver tries to reopen on later reads
  kNotActive,  // read() before activate()
  kCorrupt,    // a frame arrived but is unusable (size vs intrinsics, all zero, NaN pose); do not use
};

enum class CameraState { kUnconfigured, kConfigured, kActive, kDegraded, kLost };

struct CameraHealth {
  CameraState state = CameraState::kUnconfigured;
  std::uint64_t frames = 0;          // frames delivered
  std::uint64_t dropped = 0;         // sequence gaps
  std::uint64_t timeouts = 0;
  std::uint64_t stale = 0, frozen = 0;
  std::uint64_t reopen_attempts = 0, reopened = 0;
  std::int64_t last_frame_host_time_us = 0;
  std::string message;  // why degraded or lost; empty when healthy
};

class DepthCamera {
 public:
  virtual ~DepthCamera() = default;
  virtual DriverResult configure(const CameraConfig& config) = 0;
  virtual DriverResult activate() = 0;
  // Waits at most config.read_timeout. On kFrame, kStale and kFrozen `frame` holds the frame.
  virtual ReadStatus read(DepthFrame& frame) = 0;
  virtual CameraHealth health() const = 0;
  virtual DriverResult deactivate() = 0;
};

// The host clock of DepthFrame::host_time_us: std::chrono::steady_clock in us (simulation time
// when the process runs on the fake world's clock, common/process_clock.h), one definition for
// every back-end so host times of different cameras compare.
std::int64_t host_clock_us();

const char* to_string(ReadStatus status);
const char* to_string(CameraState state);

}  // namespace drivers
