#pragma once
// `twin diagnose`: where twin and measurement disagree, which missing effect explains it, the
// augmented material file and the report (docs/diagnosis.md; twin/diagnosis/diagnose.h).

#include <CLI/CLI.hpp>

#include "twin/diagnosis/diagnose.h"

namespace twin_cli {

struct DiagnoseArguments {
  twin::diagnosis::DiagnoseOptions options;
  bool quiet = false;
  std::string optimizer;  // "lm" or "lbfgs"; empty: the diagnosis default (kDiagnosisOptimizer)
  std::string clamp_refinement = "none";  // --clamp-refinement (clamp_refinement_option.h)
};

CLI::App* add_diagnose_command(CLI::App& app, DiagnoseArguments& arguments);

// Exit status 0 whatever the verdict; bad input throws (main prints it and exits 1).
int run_diagnose(DiagnoseArguments& arguments);

}  // namespace twin_cli
