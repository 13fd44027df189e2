// calibrate_observed: the cell's in-situ calibration (cell/learning/in_situ_calibration.h) run
// offline on a trial directory, typically the observed trial a cell run wrote
// (`cell_controller --out DIR` -> DIR/observed_trial): fit the material to every state but the
// newest from MATERIAL, judge it on the newest, and say whether a cell would adopt it.
// Exit status: 0 adopted, 3 refused, 4 failed, 1 bad input.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>

#include "cell/learning/in_situ_calibration.h"
#include "twin/model/material.h"
#include "twin/model/material_parameters.h"
#include "twin/trials/trial.h"

int main(int argc, char** argv) {
  CLI::App app{"Fit the material to a cell's observed trial as the running cell does, judged on its newest state"};
  std::string trial_dir, material_path, out_path, parameters = "tensile_N_m,shear_N_m,bending_Nm";
  cell::learning::CalibrationOptions options;
  app.add_option("TRIAL_DIR", trial_dir, "trial directory (e.g. a cell run's observed_trial)")->required();
  app.add_option("--material", material_path, "the material the cell ran (the fit starts from it)")->required();
  app.add_option("--out", out_path, "write the candidate here when it would be adopted");
  app.add_option("--parameters", parameters, "fitted parameters, comma separated (material file names)");
  app.add_option("--min-gain", options.min_gain, "the held-out error must fall by this fraction (default 0.1)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--max-evaluations", options.max_evaluations, "of the fit (default 12)")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  try {
    options.parameters.clear();
    for (std::size_t start = 0; start <= parameters.size();) {
      const std::size_t comma = std::min(parameters.find(',', start), parameters.size());
      options.parameters.push_back(twin::parse_material_parameter(parameters.substr(start, comma - start)));
      start = comma + 1;
    }
    const twin::Trial trial = twin::read_trial(trial_dir);
    const twin::Material current = twin::read_material_file(material_path);
    fmt::print("calibrate {} from {} on {}: {} states, the newest held out\n", parameters, material_path, trial_dir,
               trial.stages.size());
    std::fflush(stdout);
    const cell::learning::CalibrationResult r = cell::learning::calibrate_material(trial, current, options);
    for (const twin::ParameterEstimate& e : r.estimates) {
      fmt::print("  {:<14} {:>12.5g} -> {:>12.5g}  95 % [{:.4g}, {:.4g}]{}\n", twin::parameter_name(e.parameter),
                 twin::get_parameter(current, e.parameter), e.value, e.lower95, e.upper95,
                 e.determined ? "" : "  not determined: kept");
    }
    if (!r.fit.empty()) fmt::print("fit: {}\n", r.fit);
    fmt::print("verdict: {} ({} simulations, {:.1f} s): {}\n", cell::learning::verdict_name(r.verdict), r.simulations,
               r.seconds, r.reason);
    if (r.verdict == cell::learning::CalibrationVerdict::kAdopted && !out_path.empty()) {
      twin::write_material_file(out_path, r.candidate);
      fmt::print("wrote {}\n", out_path);
    }
    switch (r.verdict) {
      case cell::learning::CalibrationVerdict::kAdopted:
        return 0;
      case cell::learning::CalibrationVerdict::kRefused:
        return 3;
      case cell::learning::CalibrationVerdict::kFailed:
        return 4;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "calibrate_observed: {}\n", e.what());
    return 1;
  }
  return 4;
}
