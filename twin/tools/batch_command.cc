#include "batch_command.h"

#include <cstdio>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/batch/batch_runner.h"
#include "twin/distributed/rank_group.h"

namespace twin_cli {

CLI::App* add_batch_command(CLI::App& app, BatchArguments& a) {
  CLI::App* cmd = app.add_subcommand("batch", "diagnose many materials from a manifest; resumes where it stopped");
  cmd->add_option("manifest", a.manifest, "manifest file (JSON): materials with their trials, diagnose options")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", a.out, "output directory: one sub-directory per material, summary.json, summary.md")
      ->required();
  cmd->add_option("--ranks-per-material", a.ranks_per_material,
                  "under mpirun: ranks that diagnose one material together, its refit searches spread over them "
                  "(default 1: whole materials to single ranks)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--quiet", a.quiet, "no progress lines");
  return cmd;
}

int run_batch_command(const BatchArguments& a) {
  // First, so that every rank meets the same errors after MPI started (and MPI finishes last).
  const std::unique_ptr<twin::distributed::RankGroup> ranks = twin::distributed::join_ranks();
  const twin::batch::BatchManifest manifest = twin::batch::read_batch_manifest(a.manifest);
  twin::batch::BatchOptions options;
  options.out = a.out;
  options.ranks = ranks.get();
  options.ranks_per_material = a.ranks_per_material;
  if (a.ranks_per_material > ranks->size()) {
    throw std::invalid_argument(fmt::format("--ranks-per-material {}: more than the {} rank(s) of this run "
                                            "(start it with mpirun -np N, N at least {})",
                                            a.ranks_per_material, ranks->size(), a.ranks_per_material));
  }
  const std::string prefix = ranks->size() > 1 ? fmt::format("[rank {}/{}] ", ranks->rank(), ranks->size()) : "";
  if (!a.quiet) {
    options.progress = [prefix](const std::string& line) {
      fmt::print("{}{}\n", prefix, line);
      std::fflush(stdout);
    };
  }
  if (ranks->rank() == 0 && ranks->size() > 1 && !a.quiet) {
    fmt::print("twin batch: {} materials over {} ranks{}\n", manifest.materials.size(), ranks->size(),
               a.ranks_per_material > 1 ? fmt::format(" in teams of {}", a.ranks_per_material) : "");
  }
  const twin::batch::BatchResult result = twin::batch::run_batch(manifest, options);
  if (ranks->rank() != 0) return 0;  // rank 0 reports for all
  fmt::print("\n{}wrote {}/summary.md, {}/summary.json\n", twin::batch::summary_table(result), a.out, a.out);
  std::fflush(stdout);
  return result.failed > 0 ? 2 : 0;
}

}  // namespace twin_cli
