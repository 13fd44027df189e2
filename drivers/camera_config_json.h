#pragma once
// The cameras of a cell config file (JSON), as drivers::CameraConfig. Every error throws
// std::invalid_argument naming the file, the camera (index and name) and the field, and what was
// expected; unknown fields are rejected, because a misspelt key on a shop floor must not be
// silently replaced by a default.
//
// File: either an object with a "cameras" array (other top-level keys belong to other parts of
// the cell and are left alone) or the bare array. One camera:
//   {"name": "cam_left", "backend": "v4l2", "uri": "depth=/dev/video0,color=/dev/video2",
//    "serial": "",                                         (optional)
//    "depth_mode": {"width": 848, "height": 480, "fps": 30},  (optional, default 848x480@30)
//    "color_mode": {...},                                  (optional, default 848x480@30)
//    "depth_intrinsics": {"width": 848, "height": 480, "fx": 600, "fy": 600, "cx": 424,
//                         "cy": 240, "distortion": [k1, k2, p1, p2, k3]},  (distortion optional;
//                         the whole entry is optional for back-ends that know their calibration
//                         (simulated, OpenNI2); v4l2 refuses to configure without it)
//    "color_intrinsics": {...},                            (optional: no colour calibration)
//    "depth_to_color": {"translation_m": [x, y, z], "quaternion_wxyz": [w, x, y, z]},
//    "camera_to_cell": {"translation_m": [...], "rpy_deg": [roll, pitch, yaw]},
//    "depth_unit_mm": 1.0, "read_timeout_ms": 200, "stale_after_ms": 500,
//    "frozen_after_frames": 3}                             (all four optional)
// A pose gives its rotation (see pose_json.h) as a look-at point "look_at_m" [x, y, z], or
// as a unit quaternion (w first; |q| within 1e-3 of 1, then
// normalised) or as roll/pitch/yaw in degrees, R = Rz(yaw) Ry(pitch) Rx(roll). depth_to_color
// is optional (identity); camera_to_cell is required. Intrinsics sizes must equal their mode's.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drivers/depth_camera.h"

namespace drivers {

// `source` names the file in error messages.
std::vector<CameraConfig> parse_camera_configs(const nlohmann::json& document,
                                               const std::string& source);

// Reads the file; throws std::runtime_error when it cannot be read or is not JSON.
std::vector<CameraConfig> read_camera_configs(const std::string& path);

}  // namespace drivers
