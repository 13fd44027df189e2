// real_sheet_refinement: the convergence study of the independent sheet (issue 33,
// docs/independent_sheet.md). Follows one lab trial's clamp path (specimen, seed: protocol and
// stage times) on the path grid, carries every stage to grids of several spacings and solves it
// there (each grid from the one before, coarse to fine), and prints per spacing how far each
// stage's markers lie from those of the next finer grid and of the finest: mean and max over
// the markers a scan sees (not those under a closed jaw).
//   real_sheet_refinement --specimen composite --seed 1 --spacings 0.02,0.014,0.01,0.007,0.005

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include <fmt/format.h>

#include "sim_hw/scanner_lab.h"

int main(int argc, char** argv) {
  CLI::App app{"Refinement study of the scanner lab's independent sheet"};
  sim_hw::ScannerLabConfig config;
  std::vector<double> spacings = {0.02, 0.014, 0.01, 0.007, 0.005};
  std::string jaws = "rigid";
  app.add_option("--specimen", config.specimen, "composite, cloth, canvas or felt");
  app.add_option("--seed", config.seed, "the lab trial's seed");
  app.add_option("--spacings", spacings, "grid spacings (m); the finest is the reference")->delimiter(',');
  app.add_option("--path-grid-spacing-m", config.path_grid_spacing_m, "the path's grid (m; default for the material)");
  app.add_option("--jaws", jaws, "rigid or pivot");
  double bending_change = 0.01;
  app.add_option("--bending-change", bending_change,
                 "also solve the finest grid with bending times 1 + this (the markers' sensitivity; 0: skip)");
  CLI11_PARSE(app, argc, argv);
  try {
    config.truth_model = sim_hw::TruthModel::kIndependent;
    config.jaws = sim_hw::parse_jaw_kind(jaws, "--jaws");
    std::sort(spacings.begin(), spacings.end(), std::greater<>());
    const sim_hw::LabSetup setup = sim_hw::lab_setup(config);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<sim_hw::ReferenceStages> results = sim_hw::independent_refinement(
        sim_hw::reference_sheet(config), setup.truth, config.creases, setup.specimen.width_m, setup.specimen.height_m,
        setup.trial.clamps, setup.stages, setup.trial.marker_uv_m, spacings, bending_change);
    const bool sensitivity = results.size() > spacings.size();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (std::size_t k = 0; k < spacings.size(); ++k) fmt::print("{:.4f} m: {}\n", spacings[k], results[k].description);
    const sim_hw::ReferenceStages finest = results[spacings.size() - 1];
    std::vector<sim_hw::ReferenceStages> grids(results.begin(), results.begin() + static_cast<long>(spacings.size()));
    fmt::print("({:.0f} s in all; default grid for this material {:.4f} m, path grid {:.4f} m)\n\n", seconds,
               sim_hw::independent_grid_spacing_m(setup.truth), sim_hw::independent_path_spacing_m(setup.truth));
    // Markers a scan sees: not within the jaw radius of a closed clamp.
    const auto seen = [&](std::size_t s, std::size_t m) {
      return !sim_hw::hidden_under_clamp(setup.trial.clamps, setup.stages[s].poses, setup.trial.marker_uv_m[m],
                                         config.clamp_jaw_radius_m);
    };
    // Per stage, mean / max distance of the seen markers between two grids' results.
    const auto compare = [&](const sim_hw::ReferenceStages& a, const sim_hw::ReferenceStages& b) {
      std::string line;
      double worst_mean = 0, worst_max = 0;
      for (std::size_t s = 0; s < b.markers_m.size(); ++s) {
        double sum = 0, max = 0;
        int n = 0;
        for (std::size_t m = 0; m < b.markers_m[s].size(); ++m) {
          if (!seen(s, m)) continue;
          const double d = (a.markers_m[s][m] - b.markers_m[s][m]).norm();
          sum += d;
          max = std::max(max, d);
          ++n;
        }
        line += fmt::format(" {:5.2f} / {:5.2f}", 1e3 * sum / n, 1e3 * max);
        worst_mean = std::max(worst_mean, sum / n);
        worst_max = std::max(worst_max, max);
      }
      return fmt::format("{} | worst stage: mean {:.2f}, max {:.2f}", line, 1e3 * worst_mean, 1e3 * worst_max);
    };
    fmt::print("{} seed {}: seen markers, mm, mean / max per stage (stages 1-{})\n", config.specimen, config.seed,
               finest.markers_m.size());
    for (std::size_t k = 0; k + 1 < grids.size(); ++k) {
      fmt::print("spacing {:.4f} m against {:.4f} m (next) |{}\n", spacings[k], spacings[k + 1],
                 compare(grids[k], grids[k + 1]));
    }
    for (std::size_t k = 0; k + 2 < grids.size(); ++k) {
      fmt::print("spacing {:.4f} m against {:.4f} m (finest)|{}\n", spacings[k], spacings.back(),
                 compare(grids[k], grids.back()));
    }
    if (sensitivity) {
      fmt::print("bending x {:.3f} on the finest grid         |{}\n", 1.0 + bending_change,
                 compare(results.back(), finest));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "real_sheet_refinement: %s\n", e.what());
    return 2;
  }
}
