// world_truth_refinement: is the fake world's true sheet converged at the states a cell run saw?
// Re-simulates the stages of a cell run's observed trial (the grasps as measured, in order) by
// quasi-static continuation on the world's own physics (its material, jaws and sheet; the
// independent model at each grid spacing given), and prints per stage how far the sheets at the
// different spacings are from each other at the trial's markers, and how far the first spacing's
// is from the truth the run recorded (observed_trial/truth/, when present).
// Exit status: 0 done, 1 bad input, 2 a stage did not settle.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "sim_hw/true_sheet_physics.h"
#include "sim_hw/world_config.h"
#include "twin/mesh/material_point.h"
#include "twin/trials/trial.h"

namespace {

// Mean and max distance between two marker sets (m).
std::pair<double, double> distance_m(const std::vector<twin::Vec3>& a, const std::vector<twin::Vec3>& b) {
  double sum = 0.0, worst = 0.0;
  for (std::size_t m = 0; m < a.size(); ++m) {
    const double d = (a[m] - b[m]).norm();
    sum += d;
    worst = std::max(worst, d);
  }
  return {a.empty() ? 0.0 : sum / static_cast<double>(a.size()), worst};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Refinement study of the fake world's true sheet at a cell run's settled states"};
  std::string observed_dir, cell_config, world_config;
  std::vector<double> spacings_m{0.04, 0.02};
  int increments = 10;
  app.add_option("OBSERVED_TRIAL", observed_dir, "a cell run's observed_trial")->required();
  app.add_option("--config", cell_config, "the run's cell config")->required();
  app.add_option("--world", world_config, "the run's world config")->required();
  app.add_option("--spacings", spacings_m, "grid spacings of the independent sheet, m (default 0.04 0.02)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  app.add_option("--increments", increments, "quasi-static increments between stages (default 10)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  std::vector<std::vector<std::vector<twin::Vec3>>> sheets;  // per spacing, per stage, per marker
  twin::Trial trial;
  sim_hw::WorldConfig world;
  try {
    trial = twin::read_trial(observed_dir);
    world = sim_hw::read_world_config(cell_config, world_config);
  } catch (const std::exception& e) {
    fmt::print(stderr, "world_truth_refinement: {}\n", e.what());
    return 1;
  }
  // The world holds every patch turned as the ply lies in its placement.
  const auto held = [&](std::vector<twin::ClampPose> poses) {
    for (twin::ClampPose& p : poses) p.rotation = world.sheet.placement.rotation;
    return poses;
  };
  for (const double h : spacings_m) {
    sim_hw::TrueSheetOptions options = world.truth;
    options.model = sim_hw::TruthModel::kIndependent;
    options.grid_spacing_m = h;
    std::unique_ptr<sim_hw::TrueSheetPhysics> physics;
    try {
      physics = sim_hw::make_true_sheet_physics(world.sheet, world.material, options);
    } catch (const std::exception& e) {
      fmt::print(stderr, "world_truth_refinement: {}\n", e.what());
      return 1;
    }
    const twin::MaterialPointMap at_markers(physics->mesh(), trial.marker_uv_m);
    twin::VecX x = twin::place_flat(physics->mesh(), world.sheet.placement);
    std::vector<twin::ClampPose> now = held(trial.stages.front().poses);
    std::vector<std::vector<twin::Vec3>> per_stage;
    for (std::size_t s = 0; s < trial.stages.size(); ++s) {
      const std::vector<twin::ClampPose> target = held(trial.stages[s].poses), from = now;
      // The first stage is loaded onto the flat sheet at once, as the world loads it.
      const int steps = s == 0 ? 1 : increments;
      for (int k = 1; k <= steps; ++k) {
        for (std::size_t g = 0; g < now.size(); ++g) now[g] = twin::interpolate(from[g], target[g], double(k) / steps);
        const auto settled = physics->settle(trial.clamps, now, x);
        if (!settled.failure.empty()) {
          fmt::print(stderr, "world_truth_refinement: grid {} m, stage {}: {}\n", h, trial.stages[s].id, settled.failure);
          return 2;
        }
      }
      per_stage.push_back(at_markers.positions(x));
    }
    fmt::print("grid {:.3f} m: {} nodes, {} stages settled\n", h, physics->mesh().vertex_count(), per_stage.size());
    std::fflush(stdout);
    sheets.push_back(std::move(per_stage));
  }

  // The truth the run recorded, on the world's own mesh.
  std::unique_ptr<sim_hw::TrueSheetPhysics> world_physics;
  try {
    world_physics = sim_hw::make_true_sheet_physics(world.sheet, world.material, world.truth);
  } catch (const std::exception&) {
  }
  for (std::size_t s = 0; s < trial.stages.size(); ++s) {
    std::string line = fmt::format("stage {}:", trial.stages[s].id);
    for (std::size_t k = 1; k < sheets.size(); ++k) {
      const auto [mean, max] = distance_m(sheets[0][s], sheets[k][s]);
      line += fmt::format("  grid {:.3f} vs {:.3f} m: {:.2f} mm mean, {:.1f} mm max;", spacings_m[0], spacings_m[k],
                          1e3 * mean, 1e3 * max);
    }
    const std::filesystem::path truth_file =
        std::filesystem::path(observed_dir) / "truth" / (trial.stages[s].id + ".xyz");
    if (world_physics && std::filesystem::exists(truth_file)) {
      const std::vector<twin::Vec3> truth = twin::read_xyz_file(truth_file.string(), false);
      if (static_cast<int>(truth.size()) == world_physics->mesh().vertex_count()) {
        twin::VecX x(3 * static_cast<Eigen::Index>(truth.size()));
        for (std::size_t i = 0; i < truth.size(); ++i) x.segment<3>(3 * static_cast<Eigen::Index>(i)) = truth[i];
        const auto recorded = twin::MaterialPointMap(world_physics->mesh(), trial.marker_uv_m).positions(x);
        const auto [mean, max] = distance_m(sheets[0][s], recorded);
        line += fmt::format("  grid {:.3f} m quasi-static vs the run's recorded truth: {:.2f} mm mean, {:.1f} mm max",
                            spacings_m[0], 1e3 * mean, 1e3 * max);
      }
    }
    fmt::print("{}\n", line);
  }
  return 0;
}
