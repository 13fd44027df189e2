#pragma once
// A rigid pose in a cell config file: {"translation_m": [x, y, z], "quaternion_wxyz": [w, x, y, z]}
// or {"translation_m": [...], "rpy_deg": [roll, pitch, yaw]} with R = Rz(yaw) Ry(pitch) Rx(roll).
// A quaternion must be unit within 1e-3 (then normalised). Errors name the file and field.
#include <Eigen/Geometry>

#include "drivers/json_field.h"

namespace drivers {

Eigen::Isometry3d parse_pose(const JsonField& f);

}  // namespace drivers
