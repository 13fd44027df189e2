#include "drivers/frame_checks.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string_view>

namespace drivers {
namespace {

bool finite_intrinsics(const Intrinsics& k) {
  for (double v : {k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2, k.k3})
    if (!std::isfinite(v)) return false;
  return k.fx > 0 && k.fy > 0;
}

std::string size_text(const Intrinsics& k) {
  return std::to_string(k.width) + "x" + std::to_string(k.height);
}

}  // namespace

std::string corrupt_frame_reason(const DepthFrame& f) {
  const Intrinsics& d = f.depth_intrinsics;
  if (d.width <= 0 || d.height <= 0)
    return "depth intrinsics have no image size (" + size_text(d) + ")";
  const std::size_t depth_pixels = static_cast<std::size_t>(d.width) * d.height;
  if (f.depth_mm.size() != depth_pixels)
    return "depth image has " + std::to_string(f.depth_mm.size()) + " pixels, intrinsics say " +
           size_text(d) + " = " + std::to_string(depth_pixels);
  if (!finite_intrinsics(d)) return "depth intrinsics are not finite or focal lengths not > 0";
  const Intrinsics& c = f.color_intrinsics;
  if (c.width > 0 || !f.rgb.empty()) {
    const std::size_t rgb_bytes = static_cast<std::size_t>(std::max(c.width, 0)) * std::max(c.height, 0) * 3;
    if (f.rgb.size() != rgb_bytes || rgb_bytes == 0)
      return "colour image has " + std::to_string(f.rgb.size()) + " bytes, intrinsics say " +
             size_text(c) + " x 3 = " + std::to_string(rgb_bytes);
    if (!finite_intrinsics(c)) return "colour intrinsics are not finite or focal lengths not > 0";
  }
  if (!f.depth_to_color.matrix().allFinite()) return "depth_to_color extrinsic is not finite";
  if (!f.camera_to_cell.matrix().allFinite()) return "camera_to_cell extrinsic is not finite";
  if (std::all_of(f.depth_mm.begin(), f.depth_mm.end(), [](std::uint16_t v) { return v == 0; }))
    return "depth image is all zero";
  return {};
}

std::uint64_t depth_content_hash(const DepthFrame& f) {
  const std::string_view bytes(reinterpret_cast<const char*>(f.depth_mm.data()),
                               f.depth_mm.size() * sizeof(std::uint16_t));
  return std::hash<std::string_view>{}(bytes);
}

}  // namespace drivers
