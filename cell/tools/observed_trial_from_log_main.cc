// observed_trial_from_log: a cell run's settled states, from its lcm-logger log, as a trial
// directory (cell/log_settled_states.h), the same the cell writes at exit (`--out DIR` ->
// DIR/observed_trial): for `twin identify`, `twin diagnose` and `calibrate_observed`.
// Exit status: 0 written, 1 bad input, 2 no settled state in the log.
#include <fmt/format.h>

#include <CLI/CLI.hpp>

#include "cell/cell_config.h"
#include "cell/learning/cell_trial.h"
#include "cell/log_settled_states.h"
#include "twin/model/material.h"

int main(int argc, char** argv) {
  CLI::App app{"Write a cell run's settled states, read from its LCM log, as a trial directory"};
  std::string log_path, config_path, out_dir;
  app.add_option("LOG", log_path, "lcm-logger log of a cell run")->required();
  app.add_option("--config", config_path, "the run's cell config (mesh, plan, material, arms, learning)")->required();
  app.add_option("--out", out_dir, "the trial directory to write")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    const cell::CellConfig config = cell::read_cell_config(config_path);
    const twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
    const twin::Material material = twin::read_material_file(config.material_file);
    const cell::LoggedStates logged = cell::settled_states_from_log(log_path, config, plan);
    fmt::print("{} observed sheets ({} on another mesh), {} arm and {} gripper statuses, {} true sheets, {} "
               "undecodable; {} settled states\n",
               logged.observed_sheets, logged.other_mesh, logged.arm_statuses, logged.gripper_statuses, logged.truths,
               logged.undecodable, logged.states.size());
    if (logged.states.empty()) {
      fmt::print(stderr, "observed_trial_from_log: no settled state in {}\n", log_path);
      return 2;
    }
    cell::learning::write_cell_trial(out_dir, logged.states, config.sheet.mesh, plan, material);
    fmt::print("wrote {}\n", out_dir);
  } catch (const std::exception& e) {
    fmt::print(stderr, "observed_trial_from_log: {}\n", e.what());
    return 1;
  }
  return 0;
}
