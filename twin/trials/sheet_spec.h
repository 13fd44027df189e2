#pragma once
// The "sheet" object of the twin's input files (scenario, cell config, fake-world config): a
// rectangle by size and resolution, or any flat mesh file, and optionally where it lies:
//   {"width_m": 1.17, "height_m": 0.975, "target_triangles": 6000,   (or "edge_length_m")
//    "pattern": "offset_rows" | "right_triangles",                    (optional)
//    "placement": {"origin_m": [x, y, z], "rotation_deg": [r, p, y]}} (optional)
//   or {"mesh_file": "ply.obj", "placement": {...}}                   (path relative to base)
#include <string>

#include "twin/model/clamp.h"
#include "twin/base/json_field.h"
#include "twin/mesh/sheet_mesh.h"

namespace twin {

struct SheetSpec {
  SheetMesh mesh;
  std::string description;  // e.g. "rectangle 1.17 x 0.975 m, edge 0.021 m, 1539 triangles"
  SheetPlacement placement;
};

// Throws std::invalid_argument naming the file and field (from `f`); relative mesh_file paths
// are taken relative to base_directory.
SheetSpec read_sheet_spec(const JsonField& f, const std::string& base_directory);

// R = Rz(yaw) Ry(pitch) Rx(roll) from [roll, pitch, yaw] in degrees.
Mat3 rotation_from_degrees(const Vec3& roll_pitch_yaw_deg);

}  // namespace twin
