// Scene files of the registered "simulated" back-end: a scene that loads and renders, and errors
// that name the file and the field (or the mesh file and line).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "drivers/camera_registry.h"
#include "sim_hw/d415_scene_file.h"
#include "sim_hw/simulated_cameras.h"
#include "tests/sim_hw/d415_test_scenes.h"
#include "tests/support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string load_error(const fs::path& p) {
  try {
    sim_hw::load_d415_scene_file(p.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("scene file: the registered simulated back-end renders a scene file", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_sim_scene_ok");  // removed when the case ends
  const fs::path dir = tmp.str();
  write(dir / "tri.obj", "v -1 -1 0.5\nv 1 -1 0.5\nv 0 1 0.5\nf 1 2 3\n");
  write(dir / "scene.json", R"({
    "meshes": [{"name": "tri", "file": "tri.obj", "albedo": [200, 10, 10]}],
    "boxes": [{"name": "table", "min_m": [0.5, 0.5, 0], "max_m": [0.9, 0.9, 0.3]}],
    "floor": {"height_m": 0.0},
    "seed": 5, "clock": "simulated",
    "noise": {"sigma_at_1m_mm": 0, "bias_at_1m_mm": 0, "dropout_fraction": 0},
    "faults": {"drop_every_nth": 2}
  })");
  sim_hw::register_simulated_depth_cameras();
  const auto backends = drivers::depth_camera_backends();
  CHECK(std::find(backends.begin(), backends.end(), "simulated") != backends.end());
  auto cam = drivers::make_depth_camera("simulated");
  auto config = sim_hw_test::config_848("file_cam", sim_hw_test::looking_down(1.5));
  config.uri = (dir / "scene.json").string();
  REQUIRE(cam->configure(config).ok);
  REQUIRE(cam->activate().ok);
  drivers::DepthFrame f;
  REQUIRE(cam->read(f) == drivers::ReadStatus::kFrame);
  REQUIRE(cam->read(f) == drivers::ReadStatus::kFrame);
  CHECK(f.sequence == 2);  // every 2nd frame dropped, from the file's faults
  const auto& k = f.depth_intrinsics;
  CHECK(f.depth_mm[(k.height / 2) * k.width + k.width / 2] == 1000);  // the triangle at z = 0.5 m, no noise
  CHECK(f.depth_mm[5 * k.width + 60] == 1500);                         // the floor
  // The left band the right imager cannot see (b f / z = 24 px at 1.5 m) is invalid, as on a D4xx.
  CHECK(f.depth_mm[5 * k.width + 5] == 0);
}

TEST_CASE("scene file: a bumped camera sees the scene from its moved pose and still reports the configured one",
          "[camera_sim]") {
  const testing_support::TempDir tmp("camera_sim_scene_bumped");  // removed when the case ends
  const fs::path dir = tmp.str();
  // A step in the floor: 0.5 m high for x > 0, so a sideways move of the camera shows.
  write(dir / "scene.json", R"({
    "meshes": [{"name": "step", "vertices": [[0, -2, 0.5], [2, -2, 0.5], [2, 2, 0.5], [0, 2, 0.5]],
                "triangles": [[0, 1, 2], [0, 2, 3]]}],
    "floor": {"height_m": 0.0}, "seed": 5, "clock": "simulated",
    "noise": {"sigma_at_1m_mm": 0, "bias_at_1m_mm": 0, "dropout_fraction": 0, "stereo_shadow": false},
    "faults": {"bumped_from_s": 0.05, "bump_m": [0.05, 0, 0]}
  })");
  sim_hw::SimulatedD415Camera cam;
  auto config = sim_hw_test::config_848("bumped_cam", sim_hw_test::looking_down(1.5));
  config.uri = (dir / "scene.json").string();
  REQUIRE(cam.configure(config).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame before, after;
  REQUIRE(cam.read(before) == drivers::ReadStatus::kFrame);  // t = 0: in place
  REQUIRE(cam.read(after) == drivers::ReadStatus::kFrame);   // t = 1/30 s
  REQUIRE(cam.read(after) == drivers::ReadStatus::kFrame);   // t = 2/30 s: bumped 5 cm
  CHECK(after.camera_to_cell.isApprox(before.camera_to_cell));  // the driver does not know
  int changed = 0;
  for (std::size_t i = 0; i < before.depth_mm.size(); ++i) changed += before.depth_mm[i] != after.depth_mm[i];
  CHECK(changed > 1000);  // the step's edge moved in the image
  write(dir / "bad.json", R"({"meshes": [], "faults": {"bump_m": [0.01, 0]}})");
  CHECK_THAT(load_error(dir / "bad.json"), Catch::Contains("faults.bump_m"));
}

TEST_CASE("scene file: errors name the file and the field", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_sim_scene_bad");  // removed when the case ends
  const fs::path dir = tmp.str();
  write(dir / "a.json", R"({"meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0, 1, 3]]}]})");
  CHECK_THAT(load_error(dir / "a.json"), Catch::Contains("a.json") && Catch::Contains("meshes[0].triangles[0][2]") &&
                                             Catch::Contains("vertex index"));
  write(dir / "b.json", R"({"meshes": [], "noise": {"sigma_at_1m": 2}})");
  CHECK_THAT(load_error(dir / "b.json"), Catch::Contains("b.json") && Catch::Contains("noise.sigma_at_1m") &&
                                             Catch::Contains("sigma_at_1m_mm"));
  write(dir / "c.json", R"({"meshes": [], "faults": {"stale_mode": "late"}})");
  CHECK_THAT(load_error(dir / "c.json"), Catch::Contains("faults.stale_mode") && Catch::Contains("lagging"));
  write(dir / "d.json", R"({"meshes": [{"file": "broken.ply"}]})");
  write(dir / "broken.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nabc\n");
  CHECK_THAT(load_error(dir / "d.json"), Catch::Contains("broken.ply:"));
  // A mesh the scene names but that cannot be read: the error names the scene file and the field
  // as well as the mesh (found by fuzzing, tests/fuzz d415_scene: it named only "/heet.obj").
  write(dir / "g.json", R"({"meshes": [{"file": "/nonexistent/heet.obj"}]})");
  CHECK_THAT(load_error(dir / "g.json"), Catch::Contains("g.json") && Catch::Contains("meshes[0].file") &&
                                             Catch::Contains("/nonexistent/heet.obj"));
  write(dir / "e.json", R"({"floor": {}})");
  CHECK_THAT(load_error(dir / "e.json"), Catch::Contains("e.json") && Catch::Contains("'meshes' is missing"));
  write(dir / "f.json", "{ not json");
  CHECK_THAT(load_error(dir / "f.json"), Catch::Contains("f.json") && Catch::Contains("not valid JSON"));
  // Through the camera: configure fails with the same message, it does not throw.
  sim_hw::SimulatedD415Camera cam;
  auto config = sim_hw_test::config_848("c", Eigen::Isometry3d::Identity());
  config.uri = (dir / "a.json").string();
  const auto r = cam.configure(config);
  CHECK_FALSE(r.ok);
  CHECK_THAT(r.message, Catch::Contains("meshes[0].triangles[0][2]"));
  config.uri = (dir / "missing.json").string();
  CHECK_THAT(cam.configure(config).message, Catch::Contains("missing.json: cannot open"));
}

TEST_CASE("scene file: the example scene in sim_hw/scenes loads and shows sheet, table and floor", "[camera_sim]") {
  const std::string path = std::string(PROJECT_SOURCE_DIR) + "/sim_hw/scenes/d415_table_scene.json";
  sim_hw::SimulatedD415Camera cam;
  // 1.6 m in front of the sheet (-y), 1.3 m up, looking along +y and tilted 20 deg down.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(-0.35, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                  (Eigen::Matrix3d() << 1, 0, 0, 0, 0, 1, 0, -1, 0).finished();
  pose.translation() = Eigen::Vector3d(0, -1.6, 1.3);
  auto config = sim_hw_test::config_848("example", pose);
  config.uri = path;
  const auto r = cam.configure(config);
  INFO(r.message);
  REQUIRE(r.ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  REQUIRE(cam.read(f) == drivers::ReadStatus::kFrame);
  // Deproject into the cell frame and sort the points by what they lie on.
  int sheet = 0, table = 0, floor = 0;
  const auto& k = f.depth_intrinsics;
  for (int r = 0; r < k.height; ++r) {
    for (int c = 0; c < k.width; ++c) {
      const double z = f.depth_mm[r * k.width + c] / 1000.0;
      if (z == 0) continue;
      const Eigen::Vector3d p = f.camera_to_cell * Eigen::Vector3d((c - k.cx) / k.fx * z, (r - k.cy) / k.fy * z, z);
      if (std::abs(p.z() - 0.75) < 0.02 && std::abs(p.x()) < 0.58) ++table;
      else if (std::abs(p.z()) < 0.03) ++floor;
      else if (p.z() > 0.92 && p.z() < 1.58 && std::abs(p.y() - 0.05 * (1.6 - p.z()) / 0.7) < 0.02) ++sheet;
    }
  }
  CHECK(sheet > 30000);
  CHECK(table > 10000);
  CHECK(floor > 1000);
}
