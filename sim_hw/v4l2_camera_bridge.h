#pragma once
// Serves any DepthCamera (typically the simulated D415) as an emulated D415 V4L2 device: each
// frame read from the camera is published into a depth node "<prefix>_depth" (Z16) and, when the
// camera has colour, a colour node "<prefix>_color" (YUYV), which the LD_PRELOAD shim then shows
// a process as /dev/videoN. The camera's sequence numbers pass through unchanged and its device
// timestamps move onto the host's clock (drivers::host_clock_us(): CLOCK_MONOTONIC, as uvcvideo
// stamps buffers, or the fake world's simulation time when the process runs on it, which a cell
// on "clock": "sim" reads as its own) by an offset fixed at the first frame after each plug-in,
// so they still advance, stall or jump as the camera's do and its faults (dropped frames, frozen
// or stale streams) reach the V4L2 driver as they would from a real device. The camera's clock
// must run with the host's (a simulated D415 on the wall for a wall-clock reader, on the world's
// clock for a reader on it): frames of a camera slower than its reader's clock look late, i.e.
// stale. A lost camera marks the nodes dead (unplug) and its return creates them again (plug in).

#include <memory>
#include <optional>
#include <string>

#include "drivers/depth_camera.h"
#include "sim_hw/emulated_v4l2_node.h"

namespace sim_hw {

class V4l2CameraBridge {
 public:
  // `camera` must be configured and active; `config` is its config (modes). Creates the nodes;
  // throws std::runtime_error when it cannot.
  V4l2CameraBridge(drivers::DepthCamera& camera, const drivers::CameraConfig& config, std::string prefix);

  // Reads one frame (waiting at most the camera's read timeout) and publishes it. Returns the
  // camera's status.
  drivers::ReadStatus pump();

  // PREPREG_V4L2_EMULATION entries for these nodes, e.g. "/dev/video0=p_depth,/dev/video2=p_color".
  std::string emulation_spec(const std::string& depth_device, const std::string& color_device) const;
  // The v4l2 back-end's uri for those device paths.
  std::string v4l2_uri(const std::string& depth_device, const std::string& color_device) const;

  std::uint64_t published() const { return published_; }
  bool has_color() const { return config_.color_intrinsics.width > 0; }

 private:
  void create_nodes();

  drivers::DepthCamera& camera_;
  drivers::CameraConfig config_;
  std::string prefix_;
  EmulatedV4l2Node depth_, color_;
  bool unplugged_ = false;
  bool have_clock_offset_ = false;
  std::int64_t clock_offset_us_ = 0;  // CLOCK_MONOTONIC - camera device clock
  std::uint64_t published_ = 0;
  drivers::DepthFrame frame_;
};

}  // namespace sim_hw
