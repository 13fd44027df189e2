#pragma once
// Tracker configuration from JSON (nlohmann-json). Every field is optional (the defaults of
// TrackerConfig apply); unknown fields are errors, so a misspelt name cannot silently leave a
// default in place. Errors throw std::runtime_error naming the file, the field (dotted path) and
// what was expected. Layout (units in the names):
//   { "fusion":       { "pixel_stride", "min_depth_m", "max_depth_m" },
//     "segmentation": { "box_min_m": [x,y,z], "box_max_m": [x,y,z],
//                       "color": { "enabled", "max_value", "min_value", "min_saturation",
//                                  "max_saturation", "hue_deg": [min, max] (enables the hue
//                                  rule), "unknown": "keep" | "reject" } },
//     "resample":     { "voxel_m", "remove_outliers", "outlier_neighbours", "outlier_stddev" },
//     "registration": { "max_iterations", "initial_gate_m", "final_gate_m",
//                       "smoothing_length_m", "prior_weight", "converged_step_m",
//                       "observed_distance_m" },
//     "coverage":     { "radius_m", "min_points" },
//     "calibration":  { "enabled", "every_n_cycles", "voxel_m", "plane_radius_m",
//                       "min_plane_points", "min_overlap_points", "max_points",
//                       "max_median_m", "max_p90_m" },
//     "min_sheet_points": n }

#include <string>

#include "tracking/sheet_tracker.h"

namespace tracking {

// `source` names the text in error messages (a file name, "<string>").
TrackerConfig parse_tracker_config(const std::string& text, const std::string& source);
TrackerConfig load_tracker_config(const std::string& path);

}  // namespace tracking
