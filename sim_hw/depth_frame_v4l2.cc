#include "sim_hw/depth_frame_v4l2.h"

#include <stdexcept>
#include <vector>

#include "drivers/yuyv_color.h"

namespace sim_hw {

void publish_depth(EmulatedV4l2Node& node, const drivers::DepthFrame& frame) {
  const std::size_t pixels = static_cast<std::size_t>(node.width()) * node.height();
  if (frame.depth_mm.size() != pixels)
    throw std::invalid_argument("publish_depth " + node.name() + ": frame has " +
                                std::to_string(frame.depth_mm.size()) + " depth pixels, node " +
                                std::to_string(pixels));
  node.publish(reinterpret_cast<const std::uint8_t*>(frame.depth_mm.data()), pixels * 2, frame.sequence,
               frame.device_time_us);
}

void publish_color(EmulatedV4l2Node& node, const drivers::DepthFrame& frame) {
  const std::size_t pixels = static_cast<std::size_t>(node.width()) * node.height();
  if (frame.rgb.size() != pixels * 3)
    throw std::invalid_argument("publish_color " + node.name() + ": frame has " + std::to_string(frame.rgb.size()) +
                                " RGB bytes, node needs " + std::to_string(pixels * 3));
  thread_local std::vector<std::uint8_t> yuyv;
  drivers::rgb_to_yuyv(frame.rgb.data(), node.width(), node.height(), yuyv);
  node.publish(yuyv.data(), yuyv.size(), frame.sequence, frame.device_time_us);
}

}  // namespace sim_hw
