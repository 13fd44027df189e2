#pragma once
// A rigid pose in a cell config file: {"translation_m": [x, y, z], "quaternion_wxyz": [w, x, y, z]}
// or {"translation_m": [...], "rpy_deg": [roll, pitch, yaw]} with R = Rz(yaw) Ry(pitch) Rx(roll).
// or {"translation_m": [...], "look_at_m": [x, y, z]}: a camera's optical frame (z towards the
// point, x horizontal = z x up, y = z x x, pointing down in the image).
// A quaternion must be unit within 1e-3 (then normalised). Errors name the file and field.
#include <Eigen/Geometry>

#include "drivers/json_field.h"

namespace drivers {

Eigen::Isometry3d parse_pose(const JsonField& f);

}  // namespace drivers
