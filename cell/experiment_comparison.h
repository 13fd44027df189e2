#pragma once
// Two runs of one experiment side by side (issue 35's "before / after"): the results a
// cell_controller --out DIR wrote as DIR/experiment.json, read back, and a table that puts each
// state's figures of the first run beside the second's. The learning demo
// (scripts/learning_demo.sh) runs the fake cell with the config's material, then with the
// material its own states taught, and prints this.
#include <string>
#include <vector>

#include "cell/experiment_runner.h"

namespace cell {

// Reads an experiment.json (results_json's format). Throws std::invalid_argument /
// std::runtime_error naming the file and the field.
std::vector<StateResult> read_results_json(const std::string& path);

// Per state (matched by name, in the first run's order; a state missing from the second shows
// "-"): prediction error and twin vs truth, mean and max, before -> after, and the tracker's own
// error against the truth in both runs; then the means over the states both runs have.
std::string format_comparison(const std::vector<StateResult>& before, const std::vector<StateResult>& after);

}  // namespace cell
