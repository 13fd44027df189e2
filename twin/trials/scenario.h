#pragma once
// Scenario file: a sheet, its material, its clamps and the stages the clamps go through.
// The format is documented in docs/file_formats.md ("Scenario file"); in short:
//   {
//     "sheet": {"width_m": 1.17, "height_m": 0.975, "target_triangles": 6000,
//               "placement": {"origin_m": [0, 0, 1.0], "rotation_deg": [0, 0, 0]}},
//     "material_file": "composite.json"          (or "material": { ...material fields... }),
//     "clamps": [{"id": "A", "material_point_m": [0.1, 0.05], "grip_radius_m": 0.02}, ...],
//     "stages": [{"id": "1", "clamps": {"A": [0.15, 0.1, 1.0], "B": "released", ...}}, ...],
//     "solver": {"increment_m": 0.02, "residual_tolerance": 1e-8, "max_iterations": 200}
//   }
// Relative paths (material_file, mesh_file) are relative to the scenario file's folder.

#include <optional>
#include <string>
#include <vector>

#include "twin/model/clamp.h"
#include "twin/model/material.h"
#include "twin/solvers/quasi_static.h"
#include "twin/mesh/sheet_mesh.h"

namespace twin {

struct Stage {
  std::string id;
  // Per clamp (in ClampSet order): the pose for this stage. A clamp a stage does not mention
  // keeps its pose from the stage before; clamps never mentioned yet do not grip.
  std::vector<ClampPose> poses;
};

struct Scenario {
  std::string source;              // file it was read from
  SheetMesh mesh;
  std::string mesh_description;    // e.g. "rectangle 1.17 x 0.975 m, edge 0.021 m"
  SheetPlacement placement;
  Material material;
  std::vector<ClampSpec> clamps;
  std::vector<Stage> stages;
  ContinuationOptions solver;
};

// Throws std::invalid_argument / std::runtime_error naming the file and field.
Scenario read_scenario_file(const std::string& path);
Scenario scenario_from_json(const nlohmann::json& j, const std::string& source,
                            const std::string& base_directory);

}  // namespace twin
