#pragma once
// The files of `twin diagnose` (docs/diagnosis.md): OUT/verdict.json, OUT/material_augmented.json
// (only when an effect is named: the base fit's material file plus the effect, so the twin,
// identification and the cell use it with no code change) and the report (diagnosis_report.h).

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "twin/diagnosis/diagnose.h"
#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

// What run_diagnosis found on the way, for the files.
struct DiagnosisRecord {
  IdentificationResult base;                 // the base fit, with intervals
  ResidualField train_before, test_before;   // base fit's residuals
  std::vector<CandidateScore> scores;        // in the candidates' order
  std::vector<int> ranking;                  // indices into scores of the tested ones, best first
  std::vector<Refit> refits;                 // in ranking order
  double base_bic = 0.0;
  // When the base moved onto the equilibria of a refit (diagnose.cc, step 4): that refit's effect.
  std::optional<std::string> base_branch_of;
  std::string optimizer;                     // of the base fit and the refits: "lbfgs" or "lm"
};

// verdict.json's content (the contract in docs/diagnosis.md).
nlohmann::json verdict_json(const DiagnoseOutcome& outcome, const DiagnosisRecord& record);

// Writes every file into options.report and returns the terminal summary.
std::string write_diagnosis_files(const DiagnoseOptions& options, const DiagnoseOutcome& outcome,
                                  const DiagnosisRecord& record, const std::vector<CandidateEffect>& candidates);

}  // namespace twin::diagnosis
