#pragma once
// Cell + world config pairs for the fake-world tests, made from the shipped examples
// (cell/examples/fake_cell.json, sim_hw/examples/fake_world.json) in a temporary directory, with
// the changes a test needs: smaller camera modes and sheet (fast), node names unique to the
// process (CTest runs cases in parallel), and any JSON edit of either file.

#include <unistd.h>

#include <fstream>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/temp_dir.h"

namespace world_test {

inline nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in.good());
  return nlohmann::json::parse(in);
}

struct WorldFiles {
  std::string cell, world;
};

struct WorldEdits {
  int camera_width = 848, camera_height = 480, fps = 6;  // the slowest D415 mode
  int triangles = 600;
  std::function<void(nlohmann::json& cell)> cell;
  std::function<void(nlohmann::json& world)> world;
  std::function<void(nlohmann::json& plan)> plan;
};

inline WorldFiles make_world_files(const testing_support::TempDir& dir, const WorldEdits& edits = {}) {
  const std::string src = PREPREG_SOURCE_DIR;
  nlohmann::json cell = read_json(src + "/cell/examples/fake_cell.json");
  nlohmann::json world = read_json(src + "/sim_hw/examples/fake_world.json");
  nlohmann::json plan = read_json(src + "/cell/examples/four_grasp_plan.json");
  const double scale = edits.camera_width / 848.0;
  for (auto& cam : cell["cameras"]) {
    for (const char* mode : {"depth_mode", "color_mode"})
      cam[mode] = {{"width", edits.camera_width}, {"height", edits.camera_height}, {"fps", edits.fps}};
    for (const char* k : {"depth_intrinsics", "color_intrinsics"}) {
      auto& in = cam[k];
      in["width"] = edits.camera_width;
      in["height"] = edits.camera_height;
      in["fx"] = in["fx"].get<double>() * scale;
      in["fy"] = in["fy"].get<double>() * scale;
      in["cx"] = (edits.camera_width - 1) / 2.0;
      in["cy"] = (edits.camera_height - 1) / 2.0;
    }
  }
  world["material_file"] = src + "/sim_hw/examples/composite_truth.json";
  world["sheet"]["target_triangles"] = edits.triangles;
  for (auto& cam : world["cameras"])
    cam["node_prefix"] = "prepreg_worldtest_" + std::to_string(::getpid()) + "_" + cam["name"].get<std::string>();
  if (edits.cell) edits.cell(cell);
  if (edits.world) edits.world(world);
  if (edits.plan) edits.plan(plan);
  WorldFiles files{(dir / "cell.json").string(), (dir / "world.json").string()};
  testing_support::write_file(files.cell, cell.dump(2));
  testing_support::write_file(files.world, world.dump(2));
  testing_support::write_file(dir / "four_grasp_plan.json", plan.dump(2));
  return files;
}

}  // namespace world_test
