#include "batch_command.h"

#include <cstdio>

#include <fmt/format.h>

#include "twin/batch/batch_runner.h"

namespace twin_cli {

CLI::App* add_batch_command(CLI::App& app, BatchArguments& a) {
  CLI::App* cmd = app.add_subcommand("batch", "diagnose many materials from a manifest; resumes where it stopped");
  cmd->add_option("manifest", a.manifest, "manifest file (JSON): materials with their trials, diagnose options")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", a.out, "output directory: one sub-directory per material, summary.json, summary.md")
      ->required();
  cmd->add_flag("--quiet", a.quiet, "no progress lines");
  return cmd;
}

int run_batch_command(const BatchArguments& a) {
  const twin::batch::BatchManifest manifest = twin::batch::read_batch_manifest(a.manifest);
  twin::batch::BatchOptions options;
  options.out = a.out;
  if (!a.quiet) {
    options.progress = [](const std::string& line) {
      fmt::print("{}\n", line);
      std::fflush(stdout);
    };
  }
  const twin::batch::BatchResult result = twin::batch::run_batch(manifest, options);
  fmt::print("\n{}wrote {}/summary.md, {}/summary.json\n", twin::batch::summary_table(result), a.out, a.out);
  return result.failed > 0 ? 2 : 0;
}

}  // namespace twin_cli
