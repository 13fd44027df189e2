#pragma once
// The scene file of a simulated D415 (CameraConfig::uri of back-end "simulated"): a JSON object
//   {
//     "meshes": [ {"name": "sheet", "file": "sheet.ply", "albedo": [40, 40, 45]},
//                 {"name": "target", "vertices": [[x, y, z], ...], "triangles": [[0, 1, 2], ...]} ],
//     "boxes":  [ {"name": "table", "min_m": [x, y, z], "max_m": [x, y, z], "albedo": [...]} ],
//     "floor":  {"height_m": 0.0, "albedo": [170, 170, 165]},
//     "light_direction": [0.3, 0.2, 1.0], "background": [90, 90, 95],
//     "seed": 1, "clock": "simulated" | "wall" | "process",  (simulated_d415.h: SimClock)
//     "noise":  {"sigma_at_1m_mm": 1.5, "bias_at_1m_mm": 1.0, "grazing_limit_deg": 80,
//                "edge_jump_m": 0.03, "min_range_m": 0.3, "max_range_m": 10,
//                "dropout_fraction": 0.002, "stereo_shadow": true, "shadow_tolerance_m": 0.01,
//                "color_noise_counts": 2, "ambient": 0.35},
//     "faults": {"drop_probability": 0, "drop_every_nth": 0, "drop_from_s": 0, "drop_until_s": ...,
//                "frozen_from_s": ..., "frozen_until_s": ..., "frozen_sequence_advances": true,
//                "dead_from_s": ..., "dead_until_s": ..., "stale_from_s": ..., "stale_until_s": ...,
//                "stale_mode": "stopped" | "lagging", "stale_lag_s": 1.0}
//   }
// Every key but "meshes" is optional (defaults as in the structs). Coordinates are in the cell
// frame (m, z up); mesh files (PLY/OBJ, twin/mesh/mesh_io.h) are relative to the scene file. Albedo is
// RGB 0..255. The scene is static (the same snapshot at every time).

#include <string>

#include "sim_hw/simulated_d415.h"
#include "twin/base/json_field.h"

namespace sim_hw {

// Throws std::runtime_error / std::invalid_argument naming the file and field (or the mesh file
// and line) and what was expected.
SimulatedD415Options load_d415_scene_file(const std::string& path);

// The "noise" object alone (also used by the fake world's config, world_config.h).
D415NoiseConfig read_d415_noise(const twin::JsonField& noise);

}  // namespace sim_hw
