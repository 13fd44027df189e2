#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "drivers/camera_config_json.h"
#include "drivers/cell_hardware_config.h"
#include "tests/support/temp_dir.h"

namespace {

using drivers::CameraConfig;
using nlohmann::json;

json good_camera(const std::string& name) {
  return json::parse(R"({
    "name": ")" + name + R"(", "backend": "v4l2", "uri": "depth=/dev/video0,color=/dev/video2",
    "serial": "817612070123",
    "depth_mode": {"width": 848, "height": 480, "fps": 30},
    "color_mode": {"width": 1280, "height": 720, "fps": 15},
    "depth_intrinsics": {"width": 848, "height": 480, "fx": 610.5, "fy": 611.0, "cx": 424.2, "cy": 239.8},
    "color_intrinsics": {"width": 1280, "height": 720, "fx": 920, "fy": 921, "cx": 640, "cy": 360,
                         "distortion": [0.1, -0.2, 0.001, 0.002, 0.05]},
    "depth_to_color": {"translation_m": [0.015, 0, 0], "quaternion_wxyz": [1, 0, 0, 0]},
    "camera_to_cell": {"translation_m": [0.5, -1.2, 1.6], "rpy_deg": [0, 0, 90]},
    "depth_unit_mm": 1.0, "read_timeout_ms": 150, "stale_after_ms": 300, "frozen_after_frames": 4
  })");
}

// The message of the exception parse_camera_configs throws for `cameras`.
std::string error_of(const std::vector<json>& cameras) {
  try {
    json doc = json::object();
    doc["cameras"] = cameras;
    drivers::parse_camera_configs(doc, "cell.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  FAIL("no error for " << json(cameras).dump());
  return {};
}

}  // namespace

TEST_CASE("a good camera config reads every field", "[camera_config]") {
  const json doc = {{"cameras", {good_camera("cam_left"), good_camera("cam_right")}}, {"tracker", {{"x", 1}}}};
  const std::vector<CameraConfig> cams = drivers::parse_camera_configs(doc, "cell.json");
  REQUIRE(cams.size() == 2);
  const CameraConfig& c = cams[0];
  CHECK(c.name == "cam_left");
  CHECK(c.backend == "v4l2");
  CHECK(c.uri == "depth=/dev/video0,color=/dev/video2");
  CHECK(c.serial == "817612070123");
  CHECK(c.color_mode.width == 1280);
  CHECK(c.color_mode.fps == 15);
  CHECK(c.depth_intrinsics.fx == 610.5);
  CHECK(c.depth_intrinsics.cy == 239.8);
  CHECK(c.color_intrinsics.k2 == -0.2);
  CHECK(c.color_intrinsics.k3 == 0.05);
  CHECK(c.depth_to_color.translation().x() == 0.015);
  CHECK(c.read_timeout.count() == 150);
  CHECK(c.stale_after.count() == 300);
  CHECK(c.frozen_after_frames == 4);
  // yaw 90 deg: the camera's x axis points along the cell's y axis.
  const Eigen::Vector3d x_in_cell = c.camera_to_cell.linear() * Eigen::Vector3d::UnitX();
  CHECK(x_in_cell.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  CHECK(c.camera_to_cell.translation().isApprox(Eigen::Vector3d(0.5, -1.2, 1.6)));
}

TEST_CASE("camera config defaults and a file on disk", "[camera_config]") {
  json cam = good_camera("only");
  for (const char* key : {"serial", "depth_mode", "color_mode", "color_intrinsics", "depth_to_color",
                          "depth_unit_mm", "read_timeout_ms", "stale_after_ms", "frozen_after_frames"})
    cam.erase(key);
  testing_support::TempDir dir("camera_config");
  testing_support::write_file(dir / "cell.json", json::array({cam}).dump());  // a bare array
  const std::vector<CameraConfig> cams = drivers::read_camera_configs((dir / "cell.json").string());
  REQUIRE(cams.size() == 1);
  CHECK(cams[0].depth_mode.width == 848);
  CHECK(cams[0].color_intrinsics.width == 0);
  CHECK(cams[0].frozen_after_frames == 3);  // frozen within 3 frames by default
  CHECK(cams[0].depth_to_color.isApprox(Eigen::Isometry3d::Identity()));

  testing_support::write_file(dir / "broken.json", "{\"cameras\": [");
  CHECK_THROWS_WITH(drivers::read_camera_configs((dir / "broken.json").string()),
                    Catch::Contains("broken.json") && Catch::Contains("not valid JSON"));
  testing_support::write_file(dir / "huge.json", "{\"cameras\": [1e400]}");  // beyond a double (fuzzing)
  CHECK_THROWS_WITH(drivers::read_camera_configs((dir / "huge.json").string()),
                    Catch::Contains("huge.json") && Catch::Contains("not valid JSON"));
  CHECK_THROWS_WITH(drivers::read_camera_configs((dir / "missing.json").string()),
                    Catch::Contains("missing.json") && Catch::Contains("cannot open"));
  // A directory opens as a stream, then its read fails inside the parser (fuzzing, world_config).
  std::filesystem::create_directories(dir / "folder.json");
  CHECK_THROWS_WITH(drivers::read_camera_configs((dir / "folder.json").string()),
                    Catch::Contains("folder.json") && Catch::Contains("cannot read the file"));
  CHECK_THROWS_WITH(drivers::read_cell_hardware((dir / "folder.json").string()),
                    Catch::Contains("folder.json") && Catch::Contains("cannot read the file"));
}

TEST_CASE("camera config errors name the file, camera and field", "[camera_config]") {
  json typo = good_camera("cam_left");
  typo["read_timout_ms"] = 100;  // misspelt: must not fall back to the default silently
  std::string e = error_of({good_camera("cam_a"), typo});
  CHECK_THAT(e, Catch::Contains("cell.json: camera 1 (cam_left)") && Catch::Contains("'read_timout_ms'") &&
                    Catch::Contains("not a known field") && Catch::Contains("read_timeout_ms"));

  json nested = good_camera("cam_left");
  nested["depth_intrinsics"]["fz"] = 1.0;
  CHECK_THAT(error_of({nested}), Catch::Contains("'depth_intrinsics.fz'") && Catch::Contains("not a known field"));

  json q = good_camera("cam_left");
  q["camera_to_cell"] = {{"translation_m", {0, 0, 1}}, {"quaternion_wxyz", {1, 0.1, 0, 0}}};
  CHECK_THAT(error_of({q}), Catch::Contains("'camera_to_cell.quaternion_wxyz'") && Catch::Contains("unit quaternion"));

  json both = good_camera("cam_left");
  both["camera_to_cell"]["quaternion_wxyz"] = {1, 0, 0, 0};
  CHECK_THAT(error_of({both}), Catch::Contains("'camera_to_cell'") && Catch::Contains("exactly one of"));

  json short_t = good_camera("cam_left");
  short_t["depth_to_color"]["translation_m"] = {0.01, 0};
  CHECK_THAT(error_of({short_t}), Catch::Contains("'depth_to_color.translation_m'") && Catch::Contains("array of 3 numbers"));

  json no_intrinsics = good_camera("cam_left");
  no_intrinsics.erase("depth_intrinsics");  // optional: simulated and OpenNI2 cameras know theirs
  CHECK(drivers::parse_camera_configs(json::array({no_intrinsics}), "cell.json")[0].depth_intrinsics.width == 0);
  json missing = good_camera("cam_left");
  missing.erase("camera_to_cell");
  CHECK_THAT(error_of({missing}), Catch::Contains("camera 0 (cam_left): field 'camera_to_cell' is missing"));

  json size = good_camera("cam_left");
  size["depth_intrinsics"]["width"] = 1280;
  CHECK_THAT(error_of({size}), Catch::Contains("'depth_intrinsics'") && Catch::Contains("must equal depth_mode 848x480"));

  json fx = good_camera("cam_left");
  fx["depth_intrinsics"]["fx"] = -5;
  CHECK_THAT(error_of({fx}), Catch::Contains("'depth_intrinsics.fx' must be > 0"));

  json fps = good_camera("cam_left");
  fps["depth_mode"]["fps"] = "30";
  CHECK_THAT(error_of({fps}), Catch::Contains("'depth_mode.fps' must be a positive integer"));

  CHECK_THAT(error_of({good_camera("same"), good_camera("same")}), Catch::Contains("camera 1 (same)") &&
                                                                         Catch::Contains("repeats"));
  CHECK_THAT(error_of({}), Catch::Contains("cell.json: field 'cameras' must be a non-empty array"));
}

TEST_CASE("the example V4L2 cell config stays valid", "[camera_config]") {
  const std::vector<CameraConfig> cams =
      drivers::read_camera_configs(std::string(PREPREG_SOURCE_DIR) + "/drivers/examples/d415_v4l2_cell.json");
  REQUIRE(cams.size() == 3);
  CHECK(cams[0].uri.find(cams[0].serial) != std::string::npos);  // by-id paths carry the serial
  CHECK(cams[2].color_intrinsics.width == 0);                     // depth only
  for (const CameraConfig& c : cams) CHECK(std::abs(c.camera_to_cell.linear().determinant() - 1.0) < 1e-6);
}
