// calculix_opinion: CalculiX's opinion of a lab trial's held stages (docs/reference_sheet.md,
// "CalculiX's opinion"): the trial's sheet as S8R shells (sim_hw/calculix) on one grid per element
// size, the lab's protocol as static NLGEOM steps (gravity on the flat sheet, then each stage's
// jaw poses), solved by Debian's `ccx`, the markers read off each grid, and per stage the marker
// distances between CalculiX's two finest grids (its own refinement change), between CalculiX and
// the reference (the lab's truth files, when given) and the reference's own error.
//   calculix_opinion --trial T --truth T.truth --element-size-m 0.02 --element-size-m 0.01
// The stages before the first jaw that opens only: a fall is not a static step.

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sim_hw/calculix/ccx_job.h"
#include "sim_hw/calculix/shell_deck.h"
#include "sim_hw/calculix/shell_grid.h"
#include "sim_hw/calculix/shell_section.h"
#include "sim_hw/real_sheet/stage_path.h"
#include "twin/model/material.h"
#include "twin/trials/trial.h"

namespace cx = sim_hw::calculix;
namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;

namespace {

struct GridRun {
  double element_size_m = 0;
  int elements = 0, nodes = 0;
  double seconds = 0;
  std::vector<std::vector<Vec3>> markers;  // per stage reached
  std::string failure;                     // where ccx stopped, "" when every stage was reached
};

struct Distance {
  double mean_m = 0, max_m = 0;
  int count = 0;
};
Distance distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  Distance d;
  for (std::size_t m = 0; m < a.size(); ++m) {
    if (!a[m].allFinite() || !b[m].allFinite()) continue;
    const double e = (a[m] - b[m]).norm();
    d.mean_m += e, d.max_m = std::max(d.max_m, e), ++d.count;
  }
  if (d.count > 0) d.mean_m /= d.count;
  return d;
}
std::string text(const Distance& d) { return fmt::format("{:.2f} / {:.2f} mm", 1e3 * d.mean_m, 1e3 * d.max_m); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"CalculiX's opinion of a lab trial's held stages, beside the reference (calculix-ccx)"};
  std::string trial_dir, truth_dir, material_file, work_dir = "calculix_opinion", ccx = "ccx";
  std::vector<double> sizes{0.02, 0.01};
  std::size_t stage_count = 0;
  int threads = 1;
  bool reuse = false;
  std::string shear_from = "bending";
  app.add_option("--trial", trial_dir, "the trial directory (docs/file_formats.md)")->required();
  app.add_option("--truth", truth_dir, "the lab's truth directory (<stage>_true.xyz, material.json, lab.json)");
  app.add_option("--material-file", material_file, "the sheet's material (default: the truth's material.json)");
  app.add_option("--element-size-m", sizes, "CalculiX grids, coarse to fine (m; repeat)")->expected(1, 6);
  app.add_option("--stages", stage_count, "the first N stages only (default: every stage before a jaw opens)");
  app.add_option("--work-dir", work_dir, "where the decks, logs and results go (one folder per grid)");
  app.add_option("--ccx", ccx, "the CalculiX executable");
  app.add_option("--threads", threads, "ccx's threads")->check(CLI::Range(1, 64));
  app.add_option("--shear-from", shear_from,
                 "the section's in-plane shear modulus from the bending's twist D66 (folds, drape) or the membrane's "
                 "shear C66 (taut stages); the other is then off by the ratio the tool prints")
      ->check(CLI::IsMember({"bending", "membrane"}));
  app.add_flag("--reuse", reuse, "keep a grid's result when it is newer than an identical deck");
  CLI11_PARSE(app, argc, argv);
  try {
    const twin::Trial trial = twin::read_trial(trial_dir);
    if (!trial.sheet.is_rectangle()) throw std::invalid_argument(trial_dir + ": the CalculiX opinion needs a rectangular sheet");
    if (material_file.empty()) {
      if (truth_dir.empty()) throw std::invalid_argument("give --material-file or --truth (whose material.json is the sheet's)");
      material_file = (fs::path(truth_dir) / "material.json").string();
    }
    const twin::Material material = twin::read_material_file(material_file);
    const cx::ShellSection section =
        cx::shell_section(material, shear_from == "membrane" ? cx::ShearFrom::kMembrane : cx::ShearFrom::kBending);
    const double w = trial.sheet.width_m, h = trial.sheet.height_m;

    // The held stages: those before the first that opens a jaw.
    std::size_t held = 0;
    std::string stop = "";
    for (; held < trial.stages.size(); ++held) {
      bool all = true;
      for (const twin::ClampPose& p : trial.stages[held].poses) all = all && p.engaged;
      if (!all) {
        stop = fmt::format("; stage {} opens a jaw (a fall: not a static step)", trial.stages[held].id);
        break;
      }
    }
    if (stage_count > 0 && stage_count < held) held = stage_count, stop = "";
    if (held == 0) throw std::invalid_argument(trial_dir + ": no stage holds every jaw");

    std::vector<cx::DeckJaw> jaws;
    std::vector<sim_hw::real_sheet::PathStage> poses = sim_hw::real_sheet::path_stages(trial.stages);
    for (const twin::ClampSpec& c : trial.clamps) {
      jaws.push_back({c.id, c.material_point_m, c.grip_radius_m * std::sqrt(std::numbers::pi) / 2.0});
    }
    const sim_hw::real_sheet::LevelPlacement placement = sim_hw::real_sheet::level_placement(trial.clamps, poses.front().poses);
    fmt::print("calculix_opinion: {} ({} x {} m, {} markers, {} jaws), stages 1-{}{}\n  {}\n", trial_dir, w, h,
               trial.marker_uv_m.size(), jaws.size(), held, stop, section.text());
    std::fflush(stdout);

    std::vector<GridRun> runs;
    for (double size : sizes) {
      GridRun run;
      run.element_size_m = size;
      const cx::ShellGrid grid(w, h, size, cx::pad_cuts(jaws, 0, w), cx::pad_cuts(jaws, 1, h));
      run.elements = grid.element_count();
      run.nodes = grid.node_count();
      cx::ShellDeck deck;
      deck.grid = &grid;
      deck.section = section;
      deck.rotation = placement.rotation;
      deck.origin_m = placement.origin_m;
      deck.jaws = jaws;
      for (std::size_t k = 0; k < held; ++k) {
        std::vector<Vec3> d;
        for (std::size_t j = 0; j < jaws.size(); ++j) d.push_back(poses[k].poses[j].position_m - placement.to_world(jaws[j].centre_m));
        deck.stage_displacements_m.push_back(d);
      }
      const fs::path dir = fs::path(work_dir) / fmt::format("e{:.1f}mm", 1e3 * size);
      const cx::CcxJob job{dir.string(), "sheet", ccx, threads};
      const auto t = std::chrono::steady_clock::now();
      const std::vector<cx::FrdDisplacements> steps =
          cx::run_ccx(job, cx::shell_deck_text(deck, fmt::format("prepreg cell: {} on {:.1f} mm S8R", trial_dir, 1e3 * size)), reuse);
      run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
      // Stage k is step first_stage_step() + k - 1; a step cut short ends the stages reached.
      for (const cx::FrdDisplacements& s : steps) {
        if (s.step != deck.first_stage_step() + static_cast<int>(run.markers.size())) continue;
        if (!cx::step_completed(s)) break;
        run.markers.push_back(cx::sheet_points(deck, s, trial.marker_uv_m));
      }
      if (run.markers.size() < held) run.failure = fmt::format("ccx stopped before stage {} (see {})", run.markers.size() + 1, (dir / "ccx.log").string());
      for (std::size_t k = 0; k < run.markers.size(); ++k) {
        twin::write_xyz_file((dir / (trial.stages[k].id + "_markers.xyz")).string(), run.markers[k]);
      }
      fmt::print("  grid {:.1f} mm: {} S8R, {} nodes, {} of {} stages, {:.0f} s{}\n", 1e3 * size, run.elements, run.nodes,
                 run.markers.size(), held, run.seconds, run.failure.empty() ? "" : "; " + run.failure);
      std::fflush(stdout);
      runs.push_back(std::move(run));
    }

    std::optional<nlohmann::json> lab;
    if (!truth_dir.empty() && fs::exists(fs::path(truth_dir) / "lab.json")) {
      const fs::path file = fs::path(truth_dir) / "lab.json";
      std::ifstream in(file);
      try {
        lab = nlohmann::json::parse(in);
      } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(fmt::format("{}: not JSON ({})", file.string(), e.what()));
      }
    }
    for (std::size_t k = 0; k < held; ++k) {
      const std::string& id = trial.stages[k].id;
      std::string line = fmt::format("stage {}:", id);
      for (std::size_t r = 1; r < runs.size(); ++r) {
        if (runs[r - 1].markers.size() > k && runs[r].markers.size() > k) {
          line += fmt::format(" CalculiX {:.1f}->{:.1f} mm {};", 1e3 * runs[r - 1].element_size_m, 1e3 * runs[r].element_size_m,
                              text(distance(runs[r - 1].markers[k], runs[r].markers[k])));
        }
      }
      if (!truth_dir.empty()) {
        const std::string truth_file = (fs::path(truth_dir) / (id + "_true.xyz")).string();
        const std::vector<Vec3> truth = twin::read_xyz_file(truth_file, /*allow_nan=*/true);
        if (truth.size() != trial.marker_uv_m.size()) {
          throw std::runtime_error(fmt::format("{}: {} markers, the trial has {}", truth_file, truth.size(), trial.marker_uv_m.size()));
        }
        for (const GridRun& r : runs) {
          if (r.markers.size() > k) line += fmt::format(" CalculiX {:.1f} mm vs reference {};", 1e3 * r.element_size_m, text(distance(r.markers[k], truth)));
        }
        if (lab && lab->contains("truth_error")) {
          for (const auto& e : (*lab)["truth_error"]) {
            if (e.value("stage", "") == id) line += " reference's own error " + e.value("summary", std::string("?"));
          }
        }
      }
      fmt::print("{}\n", line);
    }
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "calculix_opinion: {}\n", e.what());
    return 1;
  }
}
