// world_step_benchmark: the fake world's true-sheet physics step time (ms) on the shipped
// example (sim_hw/examples/fake_world.json with cell/examples/fake_cell.json), at rest and
// while one gripper's jaw moves the sheet (LEFT, 0.1 m/s up and towards the centre for 2 s),
// as the world runs it: the linearised implicit step at the world's dt, one thread.
//   world_step_benchmark [--cell CELL.json] [--world WORLD.json]
// Prints median, 90th percentile and max per phase, and the step failures. A program that prints
// figures, not a test. Run it with OMP_WAIT_POLICY=passive, as cell_world runs itself.

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <vector>

#include "sim_hw/true_sheet.h"
#include "sim_hw/world_config.h"
#include "sim_hw/world_start.h"

namespace {

void report(const char* phase, std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  fmt::print("{:<8} steps {:4d}  median {:6.2f} ms  p90 {:6.2f} ms  max {:6.2f} ms\n", phase, ms.size(),
             ms[ms.size() / 2], ms[ms.size() * 9 / 10], ms.back());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"True-sheet physics step time of the fake world"};
  std::string cell = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/fake_cell.json";
  std::string world = std::string(PREPREG_SOURCE_DIR) + "/sim_hw/examples/fake_world.json";
  app.add_option("--cell", cell, "cell config");
  app.add_option("--world", world, "world config");
  CLI11_PARSE(app, argc, argv);

  const sim_hw::WorldConfig config = sim_hw::read_world_config(cell, world);
  const sim_hw::WorldStart start = sim_hw::plan_world_start(config);
  sim_hw::TrueSheet sheet(config.sheet, config.material, config.truth);
  const twin::SolveReport load = sheet.load(start.grasps);
  fmt::print("{} truth ({} vertices, {} triangles) of the {}: initial load {:.2f} s, {} Newton iterations, sag "
             "{:.3f} m\n",
             sim_hw::to_string(config.truth.model), sheet.mesh().vertex_count(), sheet.mesh().triangle_count(),
             config.sheet.description, load.seconds, load.iterations, sheet.sag_m());
  const sim_hw::HeldGrasp* moving = nullptr;
  for (const auto& g : start.grasps)
    if (g.clamp.id == "LEFT") moving = &g;
  if (!moving) {
    fmt::print(stderr, "world_step_benchmark: the plan has no LEFT grasp\n");
    return 1;
  }
  const int steps = static_cast<int>(2.0 / config.dt_s);
  std::vector<double> rest, motion;
  int substeps = 0;
  for (int i = 0; i < steps; ++i) {
    sheet.step(config.dt_s);
    rest.push_back(sheet.stats().last_step_ms);
  }
  const Eigen::Vector3d direction = Eigen::Vector3d(0.5, 0.5, 0.7).normalized();
  for (int i = 1; i <= steps; ++i) {
    Eigen::Isometry3d jaw = moving->jaw_pose;
    jaw.translation() += direction * 0.1 * i * config.dt_s;
    sheet.move_jaw("LEFT", jaw);
    sheet.step(config.dt_s);
    motion.push_back(sheet.stats().last_step_ms);
    substeps += sheet.stats().last_substeps;
  }
  report("rest", rest);
  report("moving", motion);
  fmt::print("failures {}, sub-steps per moving step {:.2f}, sag after the move {:.3f} m\n",
             sheet.stats().failures, static_cast<double>(substeps) / steps, sheet.sag_m());
  return 0;
}
