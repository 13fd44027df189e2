// Tracker config from JSON: values land in the right fields; bad input names the field.
#include <catch2/catch.hpp>

#include <stdexcept>

#include "tracking/tracker_config_json.h"

namespace tracking {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_tracker_config(text, "cell.json");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("tracker config: empty object gives the defaults, fields override them",
          "[tracker][config]") {
  const TrackerConfig d = parse_tracker_config("{}", "x");
  CHECK(d.fusion.pixel_stride == TrackerConfig{}.fusion.pixel_stride);
  CHECK(d.resample.voxel_m == TrackerConfig{}.resample.voxel_m);
  const TrackerConfig c = parse_tracker_config(R"({
    "fusion": {"pixel_stride": 1, "max_depth_m": 3.0},
    "segmentation": {"box_min_m": [-1, -1, 0.4], "box_max_m": [1, 1, 1.5],
                     "color": {"max_value": 0.5, "hue_deg": [340, 20], "unknown": "reject"}},
    "resample": {"voxel_m": 0.01, "remove_outliers": true},
    "registration": {"max_iterations": 3, "smoothing_length_m": 0.05, "stretch_weight": 4,
                     "use_rest_lengths": false, "cloud_stride": 2, "warm_start": false,
                     "warm_gate_m": 0.05, "warm_max_iterations": 4,
                     "warm_min_matched_fraction": 0.8},
    "coverage": {"radius_m": 0.015, "min_points": 4},
    "calibration": {"every_n_cycles": 30, "max_median_m": 0.004},
    "min_sheet_points": 500
  })",
                                               "x");
  CHECK(c.fusion.pixel_stride == 1);
  CHECK(c.fusion.max_depth_m == 3.0);
  CHECK(c.segmentation.box_min_m == Vec3(-1, -1, 0.4));
  CHECK(c.segmentation.color.max_value == 0.5);
  CHECK(c.segmentation.color.use_hue);
  CHECK(c.segmentation.color.min_hue_deg == 340);
  CHECK(c.segmentation.color.unknown == UnknownColorPolicy::kReject);
  CHECK(c.resample.remove_outliers);
  CHECK(c.registration.max_iterations == 3);
  CHECK(c.registration.smoothing_length_m == 0.05);
  CHECK(c.registration.stretch_weight == 4.0);
  CHECK_FALSE(c.registration.use_rest_lengths);
  CHECK(c.registration.cloud_stride == 2);
  CHECK_FALSE(c.registration.warm_start);
  CHECK(c.registration.warm_gate_m == 0.05);
  CHECK(c.registration.warm_max_iterations == 4);
  CHECK(c.registration.warm_min_matched_fraction == 0.8);
  CHECK(c.coverage.min_points == 4);
  CHECK(c.calibration.every_n_cycles == 30);
  CHECK(c.calibration.max_median_m == 0.004);
  CHECK(c.min_sheet_points == 500);
}

TEST_CASE("tracker config: errors name the file and the field", "[tracker][config]") {
  CHECK_THAT(error_of(R"({"fusion": {"pixel_stride": 0}})"),
             Catch::Contains("cell.json") && Catch::Contains("fusion.pixel_stride"));
  CHECK_THAT(error_of(R"({"fusion": {"min_depth_m": 1e400}})"),  // beyond a double (fuzzing)
             Catch::Contains("cell.json") && Catch::Contains("not valid JSON"));
  CHECK_THAT(error_of(R"({"resample": {"voxel_mm": 8}})"),
             Catch::Contains("unknown field 'resample.voxel_mm'"));
  CHECK_THAT(error_of(R"({"segmentation": {"box_min_m": [0, 0]}})"),
             Catch::Contains("segmentation.box_min_m"));
  CHECK_THAT(error_of(R"({"segmentation": {"color": {"unknown": "maybe"}}})"),
             Catch::Contains("segmentation.color.unknown") && Catch::Contains("\"maybe\""));
  CHECK_THAT(error_of(R"({"registration": {"final_gate_m": 0.5}})"),
             Catch::Contains("registration.final_gate_m"));
  CHECK_THAT(error_of(R"({"registration": {"warm_gate_m": 0}})"),
             Catch::Contains("registration.warm_gate_m"));
  CHECK_THAT(error_of(R"({"registration": {"warm_min_matched_fraction": 1.5}})"),
             Catch::Contains("registration.warm_min_matched_fraction"));
  CHECK_THAT(error_of(R"({"calibration": {"enabled": "yes"}})"),
             Catch::Contains("calibration.enabled"));
  CHECK_THAT(error_of("{\"fusion\": {\n  \"pixel_stride\": 2,\n}"),
             Catch::Contains("not valid JSON") && Catch::Contains("line 3"));
  CHECK_THROWS_WITH(load_tracker_config("/nonexistent/tracker.json"),
                    Catch::Contains("/nonexistent/tracker.json"));
}

}  // namespace tracking
