// reference_refinement: the convergence study of the reference sheet
// (docs/reference_sheet.md): a Kirchhoff-Love shell on B-splines (sim_hw/spline_shell). Follows
// one lab trial's clamp path (specimen, seed: protocol, stage times, hidden effect) on the
// coarsest level, carries every stage up through the levels (each span bisected, the shape
// carried exactly by knot insertion and solved again, so every level stays on the path's
// branch, falls included; with --replay-falls a stage where a jaw opens or closes falls again
// on each level from that level's stage before, which asks whether the fall's end is robust to
// the discretisation), and prints per stage how far the markers a scan sees move between levels, the
// observed order and a Richardson estimate of the finest level's own error (with Roache's GCI,
// safety factor 1.25), with each level's branch label (its folds) and lowest eigenvalue: levels
// on different branches are reported as a flip, never as a change.
//   reference_refinement --specimen composite --seed 1 --levels 3
//   reference_refinement --specimen composite --material-file wide_jaws.json  (a hidden effect)

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sim_hw/scanner_lab.h"
#include "sim_hw/spline_shell/branch_label.h"
#include "sim_hw/spline_shell/jaw_grip.h"
#include "sim_hw/spline_shell/refinement_estimate.h"
#include "sim_hw/spline_shell/shell_path.h"
#include "twin/model/material.h"

namespace ss = sim_hw::spline_shell;
namespace rs = sim_hw::real_sheet;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Where a change between two levels is: the marker that moved most and its distance from the
// nearest pad, and the mean change near the jaws (within `near_m` of a pad) and away from them,
// which tells a jaw's boundary layer from a fold or a free edge.
std::string where_text(const ss::LevelChange& c, const std::vector<ss::Vec3>& coarse, const std::vector<ss::Vec3>& fine,
                       const std::vector<bool>& counted, const std::vector<ss::Vec2>& uv,
                       const std::vector<ss::SquareJaw>& jaws, double near_m) {
  if (c.max_marker < 0 || jaws.empty()) return "";
  const auto nearest = [&](const ss::Vec2& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const ss::SquareJaw& j : jaws) d = std::min(d, ss::distance_to_pad_m(j, p));
    return d;
  };
  double sum_near = 0, sum_far = 0;
  int n_near = 0, n_far = 0;
  for (std::size_t m = 0; m < counted.size(); ++m) {
    if (!counted[m]) continue;
    const double d = (coarse[m] - fine[m]).norm();
    if (nearest(uv[m]) < near_m) sum_near += d, ++n_near;
    else sum_far += d, ++n_far;
  }
  const ss::Vec2& p = uv[c.max_marker];
  return fmt::format("largest at ({:.0f}, {:.0f}) mm, {:.0f} mm from a pad; mean {:.3f} mm within {:.0f} mm of a pad "
                     "({} markers), {:.3f} mm beyond ({})", 1e3 * p.x(), 1e3 * p.y(), 1e3 * nearest(p),
                     1e3 * sum_near / std::max(n_near, 1), 1e3 * near_m, n_near, 1e3 * sum_far / std::max(n_far, 1), n_far);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Refinement study of the scanner lab's reference sheet (B-spline Kirchhoff-Love shell)"};
  sim_hw::ScannerLabConfig config;
  int levels = 3, degree = 3;
  double span_m = 0, fine_span_m = 0, branch_tolerance_m = 0.02, significant_fold_m2 = 1e-3;
  std::size_t stage_count = 0;
  ss::FoldOptions folds;
  app.add_option("--specimen", config.specimen, "composite, cloth, canvas or felt");
  app.add_option("--seed", config.seed, "the lab trial's seed");
  std::string material_file;
  app.add_option("--material-file", material_file,
                 "the lab's true material, its effects block included (default: the specimen's; "
                 "docs/file_formats.md)");
  app.add_option("--levels", levels, "refinement levels (each bisects every span of the one before)")->check(CLI::Range(2, 6));
  app.add_option("--degree", degree, "spline degree")->check(CLI::Range(2, 4));
  app.add_option("--span-m", span_m,
                 "the coarsest level's largest span (m; default: a third of the material's bending length, at most "
                 "2 cm)");
  app.add_option("--fine-span-m", fine_span_m, "the coarsest level's span at the jaws' edges (m; default: half the largest)");
  app.add_option("--stages", stage_count, "study the trial's first N stages only (default: all)")->check(CLI::PositiveNumber);
  app.add_option("--fold-radius-m", folds.fold_radius_m, "a fold bends tighter than this (branch labels)");
  app.add_option("--branch-tolerance-m", branch_tolerance_m, "one branch: half of every significant fold within this of the other level's folds of its sign");
  app.add_option("--significant-fold-m2", significant_fold_m2, "one branch: folds of this area and more must match");
  ss::ShellPathOptions carry;
  app.add_option("--relax-to-force", carry.carry_relax_to_force,
                 "carried shapes relax by preconditioned L-BFGS to this fraction of the weight per control before "
                 "Newton's method (0: Newton only)");
  app.add_flag("--replay-falls", carry.replay_falls,
               "a stage that opens or closes a jaw falls again on each level (default: carried from the coarser "
               "level's fallen shape, on one branch)");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto start = std::chrono::steady_clock::now();
    if (!material_file.empty()) config.material_override = twin::read_material_file(material_file);
    const sim_hw::LabSetup setup = sim_hw::lab_setup(config);
    const double w = setup.specimen.width_m, h = setup.specimen.height_m;
    rs::SheetMaterial material = rs::sheet_material_from(setup.truth);
    for (const sim_hw::Crease& c : config.creases) material.creases.push_back({c.point_m, c.direction_rad, c.angle_rad, 0.015});
    const std::vector<ss::SquareJaw> jaws = ss::clamp_jaws(setup.trial.clamps, w, h);
    const std::size_t studied = stage_count > 0 ? std::min(stage_count, setup.stages.size()) : setup.stages.size();
    std::vector<rs::PathStage> stages = rs::path_stages(setup.stages);
    stages.resize(studied);
    if (span_m <= 0) span_m = sim_hw::default_shell_span_m(setup.truth);
    if (fine_span_m <= 0) fine_span_m = 0.5 * span_m;
    const double ring_m = ss::jaw_grip(material).knot_extension_m();  // wide jaws' ring edges
    ss::KnotVector ku = ss::jaw_knots(degree, w, 0, jaws, span_m, fine_span_m, ring_m);
    ss::KnotVector kv = ss::jaw_knots(degree, h, 1, jaws, span_m, fine_span_m, ring_m);
    auto model = std::make_unique<ss::ShellModel>(ss::SplinePatch(ku, kv), material, setup.trial.marker_uv_m);
    auto t = std::chrono::steady_clock::now();
    const ss::ShellPathResult path = ss::follow_path(*model, jaws, stages);
    if (!path.usable()) throw std::runtime_error("the path failed at " + path.failure);
    fmt::print("level 0: {} x {} controls (degree {}, spans {:.1f}-{:.1f} mm), path: {} increments, {} Newton "
               "iterations, {:.0f} s\n", model->patch().nu(), model->patch().nv(), degree, 1e3 * fine_span_m, 1e3 * span_m,
               path.increments, path.iterations, seconds_since(t));
    std::fflush(stdout);
    std::vector<std::vector<std::vector<ss::Vec3>>> markers;  // level, stage, marker
    std::vector<std::vector<ss::BranchLabel>> labels;           // level, stage
    std::vector<std::vector<double>> lowest_1_s2;               // level, stage
    std::vector<ss::VecX> x = path.stages;
    std::vector<ss::ShellHolds> holds = path.holds;
    const auto record = [&](ss::ShellModel& m, const std::vector<ss::VecX>& states, const std::vector<ss::ShellHolds>& h) {
      std::vector<std::vector<ss::Vec3>> per_stage;
      std::vector<ss::BranchLabel> label;
      std::vector<double> lambda;
      for (std::size_t k = 0; k < states.size(); ++k) {
        per_stage.push_back(m.marker_positions(states[k]));
        label.push_back(ss::branch_label(m.patch(), states[k], folds));
        m.set_age_s(ss::stage_age_s(m, stages[k]));
        lambda.push_back(ss::lowest_eigenvalue_1_s2(m, h[k], states[k]));
      }
      markers.push_back(std::move(per_stage));
      labels.push_back(std::move(label));
      lowest_1_s2.push_back(std::move(lambda));
    };
    record(*model, x, holds);
    for (std::size_t k = 0; k < x.size(); ++k) {
      fmt::print("  stage {}: {}; lowest eigenvalue {:.3g} 1/s^2\n", k + 1, labels.back()[k].text(), lowest_1_s2.back()[k]);
    }
    std::fflush(stdout);
    const ss::BranchMatch match{branch_tolerance_m, significant_fold_m2};
    std::vector<std::vector<bool>> counted(stages.size());  // per stage, the markers a scan sees
    for (std::size_t k = 0; k < stages.size(); ++k) {
      for (const ss::Vec2& uv : setup.trial.marker_uv_m) {
        counted[k].push_back(!sim_hw::hidden_under_clamp(setup.trial.clamps, setup.stages[k].poses, uv, config.clamp_jaw_radius_m));
      }
    }
    // Stage s's levels so far, for the estimate.
    const auto refinement = [&](std::size_t s) {
      std::vector<std::vector<ss::Vec3>> per_level;
      std::vector<ss::BranchLabel> label;
      for (std::size_t l = 0; l < markers.size(); ++l) per_level.push_back(markers[l][s]), label.push_back(labels[l][s]);
      return ss::stage_refinement(per_level, label, counted[s], match);
    };
    for (int level = 1; level < levels; ++level) {
      t = std::chrono::steady_clock::now();
      ku = ss::refined(ku), kv = ss::refined(kv);
      auto finer = std::make_unique<ss::ShellModel>(ss::SplinePatch(ku, kv), material, setup.trial.marker_uv_m);
      ss::CarriedPath carried;
      try {
        carried = ss::carry_path(*model, x, holds, *finer, jaws, stages, carry);
      } catch (const std::runtime_error& e) {
        throw std::runtime_error(fmt::format("level {}, {}", level, e.what()));
      }
      std::string replayed;
      for (int k : carried.replayed) replayed += fmt::format("{}{}", replayed.empty() ? "" : ", ", k + 1);
      fmt::print("level {}: {} x {} controls, {} L-BFGS and {} Newton iterations, {:.0f} s{}\n", level,
                 finer->patch().nu(), finer->patch().nv(), carried.relaxation_iterations, carried.iterations, seconds_since(t),
                 replayed.empty() ? "" : fmt::format(" (stage {} let go and fell again on this level)", replayed));
      std::fflush(stdout);
      record(*finer, carried.stages, carried.holds);
      // This level against the one before, as soon as it is known (a long study can be read as it goes).
      for (std::size_t k = 0; k < carried.stages.size(); ++k) {
        const ss::StageRefinement so_far = refinement(k);
        const ss::LevelChange& change = so_far.finest();
        std::vector<ss::SquareJaw> held;  // clamp_jaws keeps the clamps' order
        for (std::size_t c = 0; c < jaws.size(); ++c) {
          if (setup.stages[k].poses[c].engaged) held.push_back(jaws[c]);
        }
        fmt::print("  stage {}: {}; {}; lowest eigenvalue {:.3g} 1/s^2\n", k + 1, ss::change_text(level - 1, change),
                   labels.back()[k].text(), lowest_1_s2.back()[k]);
        const std::string where =
            where_text(change, markers[level - 1][k], markers[level][k], counted[k], setup.trial.marker_uv_m, held, 0.05);
        if (!where.empty()) fmt::print("    {}\n", where);
      }
      std::fflush(stdout);
      x = std::move(carried.stages);
      holds = std::move(carried.holds);
      model = std::move(finer);
    }
    fmt::print("\n{} seed {}: seen markers' change between levels, mm, mean / max per stage, on matching branches; "
               "observed order and the finest level's estimated error (Richardson, GCI = 1.25 x)\n", config.specimen,
               config.seed);
    for (std::size_t s = 0; s < x.size(); ++s) {
      const ss::StageRefinement r = refinement(s);
      fmt::print("stage {}:  {}\n", s + 1, ss::summary_text(r));
      std::string lambdas;
      for (int l = 0; l < levels; ++l) lambdas += fmt::format("{}{:.3g}", l ? " / " : "", lowest_1_s2[l][s]);
      fmt::print("         finest branch: {}; lowest eigenvalue per level {} 1/s^2\n", labels.back()[s].text(), lambdas);
    }
    fmt::print("({:.0f} s in all)\n", seconds_since(start));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reference_refinement: %s\n", e.what());
    return 2;
  }
}
