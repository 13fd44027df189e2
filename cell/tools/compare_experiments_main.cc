// compare_experiments: two runs of one experiment side by side, state by state (before -> after),
// from the experiment.json each `cell_controller --out DIR` wrote. Exit status: 0, 1 bad input.
#include <fmt/format.h>

#include <CLI/CLI.hpp>

#include "cell/experiment_comparison.h"

int main(int argc, char** argv) {
  CLI::App app{"Two runs of a cell experiment side by side, state by state"};
  std::string before_path, after_path;
  app.add_option("BEFORE", before_path, "experiment.json of the first run")->required();
  app.add_option("AFTER", after_path, "experiment.json of the second run")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    fmt::print("{}", cell::format_comparison(cell::read_results_json(before_path), cell::read_results_json(after_path)));
  } catch (const std::exception& e) {
    fmt::print(stderr, "compare_experiments: {}\n", e.what());
    return 1;
  }
  return 0;
}
