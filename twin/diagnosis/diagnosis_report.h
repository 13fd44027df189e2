#pragma once
// The diagnosis report (issue 6, step 4): OUT/report.md with SVG pictures in OUT/figures/, and a
// one-screen terminal summary. The caller (the diagnose command) decides the verdict and passes
// it, with its tables as rows of strings; this file only presents.
//
// Pictures: per marker stage a residual map in material coordinates (markers coloured by the
// normal component of the residual in mm on one diverging scale shared by every map, significant
// regions outlined), before and after side by side; a bar chart of the per-stage mean
// correspondence error before and after, train and held-out.
//
// A failed run never leaves a half report: everything is written into a temporary directory
// inside OUT and then renamed into place (figures first, report.md last).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "twin/diagnosis/residual_analysis.h"
#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

struct ReportTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each as long as the header
  bool empty() const { return rows.empty(); }
};

// One set of trials (train or held-out) before and, when an effect was added, after.
struct ReportPhase {
  std::string name;  // "train", "held-out"
  ResidualField before;
  ResidualAnalysis before_analysis;
  std::optional<ResidualField> after;  // same trials and stages, refit twin
  std::optional<ResidualAnalysis> after_analysis;
};

struct ReportData {
  std::string title = "Twin discrepancy diagnosis";
  std::string verdict_line;              // e.g. "effect: orthotropic_stiffness (...)"
  std::string after_label = "after";     // what "after" is, e.g. "with orthotropic_stiffness"
  double noise_floor_m = 0.0;            // sigma used (m)
  std::string noise_source;              // empty when given; else the fit whose residuals gave it
  ReportTable parameters;                // fitted parameters with intervals
  ReportTable candidates;                // the candidate ranking
  std::vector<std::string> notes;        // evidence and inputs, one line each
  std::vector<ReportPhase> phases;
};

// Writes OUT/report.md and OUT/figures/*.svg (OUT created if needed; earlier report files
// replaced). Throws std::runtime_error naming the path that could not be written.
void write_report(const ReportData& data, const std::filesystem::path& out_dir);

// At most 25 lines, at most 100 columns: verdict, noise floor, before/after error per phase,
// significant stages and regions, the structure sentences, the best candidates.
std::string terminal_summary(const ReportData& data);

}  // namespace twin::diagnosis
