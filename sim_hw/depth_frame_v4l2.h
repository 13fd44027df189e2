#pragma once
// Publishing drivers::DepthFrames into emulated V4L2 nodes the way a D415 streams them: the depth
// node gets Z16 (the frame's millimetres, i.e. depth unit 1 mm, the D415 default), the colour
// node YUYV (converted from the frame's RGB with drivers::rgb_to_yuyv, BT.601). Sequence and
// timestamp are the frame's (device_time_us should be CLOCK_MONOTONIC, see monotonic_us()).

#include "drivers/depth_camera.h"
#include "sim_hw/emulated_v4l2_node.h"

namespace sim_hw {

// Throws std::invalid_argument when the frame's depth size does not match the node's.
void publish_depth(EmulatedV4l2Node& node, const drivers::DepthFrame& frame);
// Throws std::invalid_argument when the frame's colour size does not match the node's.
void publish_color(EmulatedV4l2Node& node, const drivers::DepthFrame& frame);

}  // namespace sim_hw
