#pragma once
// Per-frame sanity checks that hold for every back-end (used by MonitoredDepthCamera). Pure
// functions of one frame, so they are cheap to test and cost no allocation on the cyclic path
// except the message of a rejected frame.

#include <cstdint>
#include <string>

#include "drivers/depth_camera.h"

namespace drivers {

// Empty when the frame is usable; otherwise why it is corrupt: image sizes that disagree with
// their intrinsics, an all-zero depth image, non-finite or non-positive intrinsics, a non-finite
// extrinsic (depth_to_color, camera_to_cell).
std::string corrupt_frame_reason(const DepthFrame& frame);

// A hash of the depth image's content (frozen-stream detection: identical images in a row).
std::uint64_t depth_content_hash(const DepthFrame& frame);

}  // namespace drivers
