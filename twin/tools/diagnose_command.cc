#include "diagnose_command.h"

#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "twin/distributed/rank_group.h"
#include "twin/trials/clamp_refinement_option.h"

namespace twin_cli {

CLI::App* add_diagnose_command(CLI::App& app, DiagnoseArguments& a) {
  twin::diagnosis::DiagnoseOptions& o = a.options;
  CLI::App* cmd = app.add_subcommand("diagnose", "find a missing effect of the twin, name it, add it, report");
  cmd->add_option("--train", o.train, "training trial directories (fitted)")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--test", o.test, "held-out trial directories (scored, not fitted)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--report", o.report, "output directory: verdict.json, report.md, material_augmented.json")
      ->required();
  cmd->add_option("--material", o.material, "material file with start values and the fixed properties")
      ->check(CLI::ExistingFile);
  cmd->add_option("--triangles", o.triangles, "triangles of the twin's sheet mesh (default 300)")->check(CLI::Range(50, 200000));
  cmd->add_option("--clamp-refinement", a.clamp_refinement,
                  "none: no refinement (default); jaws: halve the twin's edges near each clamp until they are at most "
                  "0.4 of its grip radius; or comma-separated radii (m): each halves the edges within that "
                  "distance of every clamp, in turn");
  cmd->add_option("--path-triangles", o.path_triangles,
                  "triangles of the coarse mesh a fresh simulation follows the clamps' path on when every "
                  "stage has markers and the twin is finer; 0: on the twin itself (default 300)")
      ->check(CLI::Range(0, 200000));
  cmd->add_option("--noise-mm", o.noise_mm, "measurement noise per coordinate, mm (default: estimated)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--effects", o.effects, "comma-separated candidate effects (default: all)");
  cmd->add_option("--refits", o.refits, "candidates refitted, best score first")->check(CLI::Range(1, 10));
  cmd->add_option("--optimizer", a.optimizer,
                  "of the base fit and the refits: lm (Levenberg-Marquardt, default) or lbfgs (NLopt LD_LBFGS)")
      ->check(CLI::IsMember({"lm", "lbfgs"}));
  cmd->add_flag("--quiet", a.quiet, "no progress lines");
  cmd->add_flag("!--no-discretisation-check", o.discretisation_check,
                "skip simulating the base fit on a twin of twice the triangles (the twin's discretisation "
                "error, reported beside the noise and used for the model-form check)");
  return cmd;
}

int run_diagnose(DiagnoseArguments& a) {
  // First, so that every rank meets the same errors after MPI started (and MPI finishes last).
  // Every rank runs the diagnosis alike and spreads the refits' searches; rank 0 prints and
  // writes.
  const std::unique_ptr<twin::distributed::RankGroup> ranks = twin::distributed::join_ranks();
  a.options.ranks = ranks.get();
  if (ranks->rank() != 0) a.quiet = true;
  if (!a.optimizer.empty()) a.options.optimizer = twin::optimizer_from_name(a.optimizer);
  const twin::ClampRefinement refinement = twin::parse_clamp_refinement(a.clamp_refinement);
  a.options.clamp_refinement_radii_m = refinement.radii_m;
  a.options.resolve_jaws = refinement.resolve_jaws;
  if (!a.quiet) {
    a.options.progress = [](const std::string& line) {
      fmt::print("{}\n", line);
      std::fflush(stdout);
    };
  }
  const twin::diagnosis::DiagnoseOutcome outcome = twin::diagnosis::run_diagnosis(a.options);
  if (ranks->rank() != 0) return 0;
  fmt::print("\n{}", outcome.summary_text);
  if (!outcome.summary_text.empty() && outcome.summary_text.back() != '\n') fmt::print("\n");
  const std::filesystem::path dir(a.options.report);
  fmt::print("wrote {}, {}{}\n", (dir / "verdict.json").string(), (dir / "report.md").string(),
             outcome.verdict.verdict == "effect" ? ", " + (dir / "material_augmented.json").string() : "");
  return 0;
}

}  // namespace twin_cli
