// scanner_lab: makes a scanned trial the way the paper's experiment did (sim_hw/scanner_lab.h).
//   scanner_lab --specimen composite --seed 1 --out trials/composite_1 [--truth DIR]
// The truth (material, noise-free markers) goes to DIR (default: OUT.truth), outside the trial.
//
//   scanner_lab blind --seed S --out TRIALS --truth TRUTH [--triangles N]
// A blind trial set (sim_hw/blind_trial_set.h): TRIALS/train_1, train_2, test_1 with one hidden
// effect picked from the seed; what it is goes to TRUTH only. `--effect NAME` forces the effect;
// it exists for the generator's own tests and the accuracy script, not for analysis.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include <fmt/format.h>

#include "sim_hw/blind_trial_set.h"
#include "sim_hw/scanner_lab.h"
#include "twin/trials/clamp_refinement_option.h"
#include "twin/model/material.h"

namespace {

int run_blind(const sim_hw::BlindSetConfig& config, const std::string& out, const std::string& truth) {
  sim_hw::check_blind_directories(out, truth);  // before minutes of simulation, not after
  const sim_hw::BlindTrialSet set = sim_hw::make_blind_trial_set(config);
  sim_hw::write_blind_trial_set(set, out, truth);
  // Says nothing about the effect: whoever runs this may be the one analysing the trials.
  // Nor its solver's effort, which differs by effect: the model's name only.
  fmt::print("scanner lab: blind set, {} seed {}, {} truth: {} trials -> {} (truth in {})\n", config.specimen,
             config.seed, sim_hw::to_string(config.truth_model), set.trials.size(), out, truth);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Scanner lab: simulated scanned trials of a clamped sheet (paper section 4.2)"};
  sim_hw::ScannerLabConfig config;
  std::string out, truth, material_file;
  app.add_option("--specimen", config.specimen, "composite, cloth, canvas or felt");
  app.add_option("--seed", config.seed, "random seed (clamp places, moves, noise)");
  app.add_option("--out", out, "trial directory to write (required)");
  app.add_option("--truth", truth, "directory for the truth (default: OUT.truth)");
  app.add_option("--material-file", material_file, "the lab's true material (default: the specimen's)");
  std::string truth_model = "spline_shell", jaws = "rigid";
  app.add_option("--truth-model", truth_model,
                 "spline_shell: the reference shell on B-splines, converging, its own error in lab.json (default; "
                 "docs/reference_sheet.md; minutes per trial); independent: the lab's finite-difference plate; twin: "
                 "the twin's shell model (the twin scoring itself)");
  app.add_option("--shell-levels", config.shell_levels,
                 "spline_shell: bisections above its coarsest level (spans a third of the material's bending length, at "
                 "most 2 cm, half that at the jaws; default 1)")
      ->check(CLI::Range(0, 3));
  app.add_option("--grid-spacing-m", config.grid_spacing_m,
                 "independent model: largest grid spacing (m; default: min(2 cm, 0.3 bending length))");
  app.add_option("--path-grid-spacing-m", config.path_grid_spacing_m,
                 "independent model: grid spacing (m) the clamps' path is followed on (default: for the material)");
  app.add_option("--jaws", jaws,
                 "rigid (default) or pivot (the sheet turns in the jaws; --truth-model independent only)");
  app.add_option("--reference-triangles", config.reference_triangles, "twin model: triangles of the reference sheet");
  std::string reference_refinement = "jaws";
  app.add_option("--reference-clamp-refinement", reference_refinement,
                 "twin model: jaws: halve the reference's edges near each clamp until they are at most 0.4 of its grip radius "
                 "(default); or comma-separated radii (m): each halves the edges within that distance of every "
                 "clamp, in turn; none: the uniform mesh");
  app.add_option("--marker-noise-m", config.marker_noise_m, "marker position noise, 1 sigma per axis (m)");
  app.add_flag("!--no-scans", config.raw_scans, "do not write raw scan points");
  app.add_option("--scans-per-stage", config.scans_per_stage,
                 "scan each pose this many times, each later than the one before, clamps untouched (default 1)")
      ->check(CLI::Range(1, 26));

  sim_hw::BlindSetConfig blind;
  std::string blind_out, blind_truth, forced;
  CLI::App* blind_app = app.add_subcommand("blind", "a trial set with one hidden effect chosen by the seed");
  blind_app->add_option("--seed", blind.seed, "random seed (effect, magnitude, protocols, noise)");
  blind_app->add_option("--out", blind_out, "directory for train_1, train_2, test_1")->required();
  blind_app->add_option("--truth", blind_truth, "directory for the hidden effect (not inside --out)")->required();
  std::string blind_truth_model = "spline_shell", blind_jaws = "rigid";
  blind_app->add_option("--truth-model", blind_truth_model, "spline_shell (default), independent or twin, as for a trial");
  blind_app->add_option("--grid-spacing-m", blind.grid_spacing_m, "independent model: largest grid spacing (m)");
  blind_app->add_option("--jaws", blind_jaws, "rigid (default) or pivot (with --truth-model independent)");
  blind_app->add_option("--triangles", blind.triangles, "twin model: triangles of the reference sheet (the twin's mesh)");
  blind_app->add_option("--specimen", blind.specimen, "composite, cloth, canvas or felt");
  blind_app->add_option("--effect", forced, "force the hidden effect (generator tests only)");
  blind_app->add_flag("--scans", blind.raw_scans, "also write raw scan points (large)");
  CLI11_PARSE(app, argc, argv);
  try {
    if (blind_app->parsed()) {
      if (!forced.empty()) blind.forced_effect = forced;
      blind.truth_model = sim_hw::parse_truth_model(blind_truth_model, "--truth-model");
      blind.jaws = sim_hw::parse_jaw_kind(blind_jaws, "--jaws");
      return run_blind(blind, blind_out, blind_truth);
    }
    if (out.empty()) {
      std::fprintf(stderr, "--out is required\nRun with --help for more information.\n");
      return 106;  // CLI11's exit code for a missing required option, as before
    }
    const twin::ClampRefinement refinement =
        twin::parse_clamp_refinement(reference_refinement, "--reference-clamp-refinement");
    config.truth_model = sim_hw::parse_truth_model(truth_model, "--truth-model");
    config.jaws = sim_hw::parse_jaw_kind(jaws, "--jaws");
    config.reference_resolves_jaws = refinement.resolve_jaws;
    config.reference_clamp_refinement_radii_m = refinement.radii_m;
    if (!material_file.empty()) config.material_override = twin::read_material_file(material_file);
    const sim_hw::LabTrial lab = sim_hw::make_lab_trial(config);
    if (truth.empty()) truth = out + ".truth";
    sim_hw::write_lab_trial(lab, config, out, truth);
    int hidden = 0;
    for (const auto& stage : lab.trial.stages) hidden += static_cast<int>(stage.observed.markers_m.size()) - stage.observed.seen_marker_count();
    fmt::print("scanner lab: {} seed {}: {} stages, {} markers, {} hidden under clamps in all, {} -> {} (truth in {})\n",
               config.specimen, config.seed, lab.trial.stages.size(), lab.trial.marker_uv_m.size(), hidden,
               lab.reference_description, out, truth);
    for (std::size_t s = 0; s < lab.truth_error.size(); ++s) {
      fmt::print("  truth's own error, stage {}: {} (seen markers' change between levels, mean / max)\n",
                 lab.trial.stages[s].id, lab.truth_error[s].text);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scanner_lab: %s\n", e.what());
    return 2;
  }
}
