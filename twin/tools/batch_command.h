#pragma once
// `[mpirun -np N] twin batch MANIFEST --out DIR [--ranks-per-material K]`: diagnoses every
// material of a manifest, resumable, whole materials spread over the MPI ranks (or over teams of
// K ranks, each material's refit searches over its team) when started by mpirun
// (twin/batch/batch_runner.h; docs/batch.md).

#include <string>

#include <CLI/CLI.hpp>

namespace twin_cli {

struct BatchArguments {
  std::string manifest, out;
  int ranks_per_material = 1;
  bool quiet = false;
};

CLI::App* add_batch_command(CLI::App& app, BatchArguments& arguments);

// Exit status: 0 every material done, 2 some failed (each has its failed.json and summary row);
// bad input throws (main prints it and exits 1).
int run_batch_command(const BatchArguments& arguments);

}  // namespace twin_cli
