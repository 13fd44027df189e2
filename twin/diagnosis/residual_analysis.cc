#include "twin/diagnosis/residual_analysis.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/diagnosis/residual_structure.h"

namespace twin::diagnosis {
namespace {

// Sum of squares of a set of samples as a (not yet judged) chi-square test.
ChiSquareTest make_test(const ResidualField& field, const std::vector<int>& idx, double sigma_m, double charged) {
  ChiSquareTest t;
  double ss = 0.0;
  for (int i : idx) ss += field.samples[i].residual_m.squaredNorm();
  t.samples = static_cast<int>(idx.size());
  if (t.samples == 0) return t;
  t.chi_square = ss / (sigma_m * sigma_m);
  t.dof = std::max(1.0, 3.0 * t.samples - charged);
  t.p_value = chi_square_upper_tail(t.chi_square, t.dof);
  t.rms_m = std::sqrt(ss / (3.0 * t.samples));
  return t;
}

std::string region_name(int row, int col, const AnalysisOptions& o) {
  if (o.region_rows == 3 && o.region_cols == 3) {
    static const char* kPart[] = {"low", "mid", "high"};
    return fmt::format("u {} / v {}", kPart[col], kPart[row]);
  }
  return fmt::format("region (v row {}, u col {})", row, col);
}

std::string fmt_p(double p) { return p < 1e-4 ? fmt::format("{:.1e}", p) : fmt::format("{:.4f}", p); }

void write_sentences(const ResidualField& field, const AnalysisOptions& o, ResidualAnalysis& a) {
  auto& out = a.sentences;
  const ChiSquareTest& t = a.overall;
  if (t.significant)
    out.push_back(fmt::format("The residual exceeds the noise: RMS {:.3f} mm per coordinate against sigma {:.3f} mm "
                              "(chi2 {:.0f} for {:.0f} dof, p = {}).",
                              1e3 * t.rms_m, 1e3 * a.sigma_m, t.chi_square, t.dof, fmt_p(t.p_value)));
  else
    out.push_back(fmt::format("The residual is consistent with noise: RMS {:.3f} mm per coordinate against sigma "
                              "{:.3f} mm (chi2 {:.0f} for {:.0f} dof, p = {}).",
                              1e3 * t.rms_m, 1e3 * a.sigma_m, t.chi_square, t.dof, fmt_p(t.p_value)));
  std::vector<std::string> stages, regions;
  for (std::size_t s = 0; s < a.stages.size(); ++s) {
    if (a.stages[s].test.significant)
      stages.push_back(fmt::format("{} ({:.2f} mm)", field.stages[s].label, 1e3 * a.stages[s].test.rms_m));
    for (const RegionResult& r : a.stages[s].regions)
      if (r.test.significant) regions.push_back(field.stages[s].label + " " + region_name(r.row, r.col, o));
  }
  if (!stages.empty())
    out.push_back(fmt::format("Significant in {} of {} stages: {}.", stages.size(), a.stages.size(),
                              fmt::join(stages, ", ")));
  if (!regions.empty()) {
    const std::size_t shown = std::min<std::size_t>(regions.size(), 6);
    out.push_back(fmt::format("Significant regions ({}): {}{}.", regions.size(),
                              fmt::join(regions.begin(), regions.begin() + static_cast<std::ptrdiff_t>(shown), "; "),
                              regions.size() > shown ? "; ..." : ""));
  }
  const DirectionStructure& d = a.direction;
  const std::string shares = fmt::format("(a cubic in u explains {:.0f} % of the normal residual's variance, in v "
                                         "{:.0f} %)",
                                         100 * d.explained_by_u, 100 * d.explained_by_v);
  if (d.direction == "u") out.push_back("The residual varies mainly along u, the weft direction " + shares + ".");
  else if (d.direction == "v") out.push_back("The residual varies mainly along v, the warp direction " + shares + ".");
  else if (d.p_u < o.alpha && d.p_v < o.alpha)
    out.push_back("The residual varies along both u and v " + shares + ".");
  for (const Correlation& c : a.correlations) {
    if (!c.notable) continue;
    const bool stage_level = c.quantity == "stage load" || c.quantity == "stage age";
    const std::string what = stage_level ? "The stages' RMS residual" : "|residual|";
    const std::string trend = c.r > 0 ? "grows with" : "shrinks with";
    out.push_back(fmt::format("{} {} {} (r = {:.2f}, p = {}, {} {}).", what, trend, c.quantity, c.r, fmt_p(c.p_value),
                              c.samples, stage_level ? "stages" : "markers"));
  }
}

}  // namespace

bool ResidualAnalysis::any_significant() const {
  return overall.significant || significant_stage_count() > 0 || significant_region_count() > 0;
}

int ResidualAnalysis::significant_stage_count() const {
  int n = 0;
  for (const StageResult& s : stages) n += s.test.significant ? 1 : 0;
  return n;
}

int ResidualAnalysis::significant_region_count() const {
  int n = 0;
  for (const StageResult& s : stages)
    for (const RegionResult& r : s.regions) n += r.test.significant ? 1 : 0;
  return n;
}

ResidualAnalysis analyse_residuals(const ResidualField& field, double sigma_m, const AnalysisOptions& options) {
  if (!(sigma_m > 0.0) || !std::isfinite(sigma_m))
    throw std::invalid_argument(fmt::format("residual analysis: noise sigma must be positive and finite, got {}", sigma_m));
  if (field.samples.empty()) throw std::invalid_argument("residual analysis: the residual field has no samples");
  if (options.region_rows < 1 || options.region_cols < 1 || !(options.alpha > 0.0 && options.alpha < 1.0))
    throw std::invalid_argument("residual analysis: need region rows, cols >= 1 and alpha in (0, 1)");
  ResidualAnalysis a;
  a.sigma_m = sigma_m;
  std::vector<int> all(field.samples.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  a.overall = make_test(field, all, sigma_m, field.fitted_parameters);
  a.tests = 1;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    StageResult result;
    const std::vector<int> idx = field.samples_of_stage(s);
    result.test = make_test(field, idx, sigma_m, 0.0);
    a.tests += result.test.tested() ? 1 : 0;
    const FieldTrial& trial = field.trials.at(field.stages[s].trial);
    const Vec2 size = trial.sheet_max_uv_m - trial.sheet_min_uv_m;
    const Vec2 cell(size.x() / options.region_cols, size.y() / options.region_rows);
    std::vector<std::vector<int>> members(static_cast<std::size_t>(options.region_rows) * options.region_cols);
    for (int i : idx) {
      const Vec2 rel = field.samples[i].uv_m - trial.sheet_min_uv_m;
      const int col = std::clamp(static_cast<int>(std::floor(rel.x() / cell.x())), 0, options.region_cols - 1);
      const int row = std::clamp(static_cast<int>(std::floor(rel.y() / cell.y())), 0, options.region_rows - 1);
      members[static_cast<std::size_t>(row) * options.region_cols + col].push_back(i);
    }
    for (int row = 0; row < options.region_rows; ++row)
      for (int col = 0; col < options.region_cols; ++col) {
        RegionResult r;
        r.row = row;
        r.col = col;
        r.min_uv_m = trial.sheet_min_uv_m + Vec2(col * cell.x(), row * cell.y());
        r.max_uv_m = r.min_uv_m + cell;
        const auto& m = members[static_cast<std::size_t>(row) * options.region_cols + col];
        if (static_cast<int>(m.size()) >= options.min_region_samples) {
          r.test = make_test(field, m, sigma_m, 0.0);
          ++a.tests;
        }
        result.regions.push_back(r);
      }
    a.stages.push_back(result);
  }
  a.bonferroni_level = options.alpha / a.tests;
  auto judge = [&](ChiSquareTest& t) { t.significant = t.tested() && t.p_value < a.bonferroni_level; };
  judge(a.overall);
  for (StageResult& s : a.stages) {
    judge(s.test);
    for (RegionResult& r : s.regions) judge(r.test);
  }
  a.direction = analyse_direction(field, sigma_m, options.alpha);
  a.correlations = analyse_correlations(field, options.alpha);
  write_sentences(field, options, a);
  return a;
}

}  // namespace twin::diagnosis
