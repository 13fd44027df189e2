// truth_trial: on fake hardware, what a cell's observed trial would have been with a perfect
// tracker. Reads the observed trial a cell run wrote (cell_controller --out DIR ->
// DIR/observed_trial, with truth/<stage>.xyz: the world's true sheet at each settled state, on
// the world's own mesh) and writes the same trial with every marker replaced by the true sheet at
// the marker's material point (noise-free, every marker seen). Fitting both (calibrate_observed,
// twin identify) tells the tracker's part of a misfit from the model's.
// Exit status: 0 written, 1 bad input (a missing truth file, a truth on another mesh).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "sim_hw/true_sheet_physics.h"
#include "sim_hw/world_config.h"
#include "twin/mesh/material_point.h"
#include "twin/trials/trial.h"

int main(int argc, char** argv) {
  CLI::App app{"Replace an observed trial's markers by the fake world's true sheet at the same states"};
  std::string observed_dir, cell_config, world_config, out_dir;
  app.add_option("OBSERVED_TRIAL", observed_dir, "a cell run's observed_trial (with truth/)")->required();
  app.add_option("--config", cell_config, "the run's cell config")->required();
  app.add_option("--world", world_config, "the run's world config")->required();
  app.add_option("--out", out_dir, "the trial directory to write")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    twin::Trial trial = twin::read_trial(observed_dir);
    const sim_hw::WorldConfig world = sim_hw::read_world_config(cell_config, world_config);
    // The world's true sheet is meshed by its physics (a grid for the independent model).
    const auto physics = sim_hw::make_true_sheet_physics(world.sheet, world.material, world.truth);
    const twin::SheetMesh& truth_mesh = physics->mesh();
    const twin::MaterialPointMap at_markers(truth_mesh, trial.marker_uv_m);
    double moved_sum_m = 0.0;
    int moved_count = 0;
    for (twin::TrialStage& stage : trial.stages) {
      const std::filesystem::path file = std::filesystem::path(observed_dir) / "truth" / (stage.id + ".xyz");
      if (!std::filesystem::exists(file)) {
        throw std::runtime_error(fmt::format("{}: missing (the run had no SIM_SHEET_TRUTH at stage {})", file.string(),
                                             stage.id));
      }
      const std::vector<twin::Vec3> truth = twin::read_xyz_file(file.string(), false);
      if (static_cast<int>(truth.size()) != truth_mesh.vertex_count()) {
        throw std::runtime_error(fmt::format("{}: {} points, the world's true sheet has {} vertices (another world "
                                             "config?)",
                                             file.string(), truth.size(), truth_mesh.vertex_count()));
      }
      twin::VecX x(3 * static_cast<Eigen::Index>(truth.size()));
      for (std::size_t i = 0; i < truth.size(); ++i) x.segment<3>(3 * static_cast<Eigen::Index>(i)) = truth[i];
      const std::vector<twin::Vec3> markers = at_markers.positions(x);
      for (std::size_t m = 0; m < markers.size(); ++m) {
        if (!stage.observed.markers_m[m].allFinite()) continue;
        moved_sum_m += (markers[m] - stage.observed.markers_m[m]).norm();
        ++moved_count;
      }
      stage.observed.markers_m = markers;
    }
    twin::write_trial(trial, out_dir);
    fmt::print("truth_trial: {} stages written to {}; the tracked markers were {:.2f} mm mean from the truth at "
               "their material points ({} seen markers)\n",
               trial.stages.size(), out_dir, moved_count ? 1e3 * moved_sum_m / moved_count : 0.0, moved_count);
  } catch (const std::exception& e) {
    fmt::print(stderr, "truth_trial: {}\n", e.what());
    return 1;
  }
  return 0;
}
