#include "sim_hw/v4l2_camera_bridge.h"

#include <linux/videodev2.h>

#include "sim_hw/depth_frame_v4l2.h"

namespace sim_hw {

V4l2CameraBridge::V4l2CameraBridge(drivers::DepthCamera& camera, const drivers::CameraConfig& config,
                                   std::string prefix)
    : camera_(camera), config_(config), prefix_(std::move(prefix)) {
  create_nodes();
}

void V4l2CameraBridge::create_nodes() {
  depth_ = EmulatedV4l2Node::create(prefix_ + "_depth", V4L2_PIX_FMT_Z16, config_.depth_mode.width,
                                    config_.depth_mode.height, config_.depth_mode.fps);
  if (has_color())
    color_ = EmulatedV4l2Node::create(prefix_ + "_color", V4L2_PIX_FMT_YUYV, config_.color_mode.width,
                                      config_.color_mode.height, config_.color_mode.fps);
}

drivers::ReadStatus V4l2CameraBridge::pump() {
  const drivers::ReadStatus status = camera_.read(frame_);
  switch (status) {
    case drivers::ReadStatus::kLost:
      if (!unplugged_) {
        depth_.mark_dead();
        color_.mark_dead();
        unplugged_ = true;
      }
      return status;
    case drivers::ReadStatus::kFrame:
    case drivers::ReadStatus::kStale:
    case drivers::ReadStatus::kFrozen:
    case drivers::ReadStatus::kCorrupt:
      break;
    default:
      return status;
  }
  if (unplugged_) {  // the camera is back: a fresh device under the same names
    create_nodes();
    unplugged_ = false;
    have_clock_offset_ = false;
  }
  if (!have_clock_offset_) {
    clock_offset_us_ = drivers::host_clock_us() - frame_.device_time_us;
    have_clock_offset_ = true;
  }
  frame_.device_time_us += clock_offset_us_;
  if (frame_.depth_mm.size() * 2 == depth_.frame_bytes()) {
    publish_depth(depth_, frame_);
  } else {
    // A frame whose size does not fit the node (a corrupt one) goes out short, as a damaged USB
    // transfer would, so the driver side sees it.
    const std::size_t depth_bytes = std::min(frame_.depth_mm.size() * 2, depth_.frame_bytes());
    depth_.publish(reinterpret_cast<const std::uint8_t*>(frame_.depth_mm.data()), depth_bytes, frame_.sequence,
                   frame_.device_time_us);
  }
  if (color_.valid() && frame_.rgb.size() == static_cast<std::size_t>(color_.width()) * color_.height() * 3)
    publish_color(color_, frame_);
  ++published_;
  return status;
}

std::string V4l2CameraBridge::emulation_spec(const std::string& depth_device, const std::string& color_device) const {
  std::string spec = depth_device + "=" + prefix_ + "_depth";
  if (has_color()) spec += "," + color_device + "=" + prefix_ + "_color";
  return spec;
}

std::string V4l2CameraBridge::v4l2_uri(const std::string& depth_device, const std::string& color_device) const {
  return "depth=" + depth_device + (has_color() ? ",color=" + color_device : "");
}

}  // namespace sim_hw
