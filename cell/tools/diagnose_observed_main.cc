// diagnose_observed: the cell's discrepancy workflow (cell/learning/in_situ_diagnosis.h) run
// offline on a trial directory, typically the observed trial a cell run wrote (`cell_controller
// --out DIR` -> DIR/observed_trial, or `observed_trial_from_log` from an lcm-logger log): find
// what the twin misses on every state but the newest, name the effect with twin diagnose's rules,
// add it, and say whether a cell would put it into its twin (judged on the newest state).
// With --config, the cell config's learning settings (diagnosis_noise_mm, diagnosis_effects,
// diagnosis_max_evaluations, min_gain) and its material are the defaults: the diagnosis the cell
// itself would run.
// Exit status: 0 adopted, 3 no effect named or refused, 4 failed, 1 bad input.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "cell/cell_config.h"
#include "cell/learning/in_situ_diagnosis.h"
#include "twin/model/material.h"
#include "twin/trials/trial.h"

int main(int argc, char** argv) {
  CLI::App app{"Find, name and add what the twin misses on a cell's observed trial, as the running cell does"};
  std::string trial_dir, material_path, out_dir, config_path;
  bool quiet = false;
  cell::learning::DiagnosisOptions options;
  app.add_option("TRIAL_DIR", trial_dir, "trial directory (e.g. a cell run's observed_trial)")->required();
  app.add_option("--config", config_path, "cell config: its learning settings and material are the defaults");
  app.add_option("--material", material_path, "the material the cell ran (the diagnosis starts from it; default: the config's)");
  app.add_option("--out", out_dir, "output directory: train/, held_out/, report/ (verdict.json, report.md, figures)")
      ->required();
  app.add_option("--noise-mm", options.noise_mm, "the tracker's error per coordinate, mm (default: estimated)")
      ->check(CLI::PositiveNumber);
  app.add_option("--effects", options.effects, "candidate effects, comma separated (default: those a cell's states carry)");
  app.add_option("--refits", options.refits, "candidates refitted, best score first (default 2)")->check(CLI::Range(1, 10));
  app.add_option("--base-evaluations", options.base_evaluations, "budget of the base fit (default 12)")
      ->check(CLI::PositiveNumber);
  app.add_option("--refit-evaluations", options.refit_evaluations, "budget of each start of a refit (default 12)")
      ->check(CLI::PositiveNumber);
  app.add_option("--min-gain", options.min_gain, "a named effect must cut the held-out error by this fraction (0.1)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_flag("--quiet", quiet, "no progress lines");
  // Options given on the command line win over the config's.
  CLI11_PARSE(app, argc, argv);

  try {
    if (!config_path.empty()) {
      const cell::CellConfig config = cell::read_cell_config(config_path);
      const cell::learning::DiagnosisOptions& c = config.learning.diagnosis;
      if (app.count("--noise-mm") == 0) options.noise_mm = c.noise_mm;
      if (app.count("--effects") == 0) options.effects = c.effects;
      if (app.count("--base-evaluations") == 0) options.base_evaluations = c.base_evaluations;
      if (app.count("--refit-evaluations") == 0) options.refit_evaluations = c.refit_evaluations;
      if (app.count("--min-gain") == 0) options.min_gain = config.learning.calibration.min_gain;
      if (material_path.empty()) material_path = config.material_file;
    }
    if (material_path.empty()) throw std::invalid_argument("--material: needed (or --config with a twin.material_file)");
    const twin::Trial trial = twin::read_trial(trial_dir);
    const twin::Material current = twin::read_material_file(material_path);
    if (!quiet) {
      options.progress = [](const std::string& line) {
        fmt::print("{}\n", line);
        std::fflush(stdout);
      };
    }
    fmt::print("diagnose {} from {}: {} states, the newest held out\n", trial_dir, material_path, trial.stages.size());
    std::fflush(stdout);
    const cell::learning::DiagnosisResult r = cell::learning::diagnose_states(trial, current, out_dir, options);
    if (r.ran) fmt::print("{}", r.outcome.summary_text);
    fmt::print("cell: {} ({:.1f} s): {}\n", cell::learning::adoption_name(r.adoption), r.seconds, r.reason);
    if (r.ran) fmt::print("report: {}/report.md\n", r.report_directory);
    switch (r.adoption) {
      case cell::learning::EffectAdoption::kAdopted:
        return 0;
      case cell::learning::EffectAdoption::kNotNamed:
      case cell::learning::EffectAdoption::kRefused:
        return 3;
      case cell::learning::EffectAdoption::kFailed:
        return 4;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "diagnose_observed: {}\n", e.what());
    return 1;
  }
  return 4;
}
