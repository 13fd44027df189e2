#include "twin/diagnosis/stage_weights.h"

#include <algorithm>
#include <cmath>

namespace twin::diagnosis {

StageWeights outlier_stage_weights(const IdentificationProblem::Evaluation& evaluation,
                                   const std::vector<std::string>& trial_names, double ratio) {
  StageWeights out;
  struct Sum {
    double squares = 0.0;
    int count = 0;
  };
  std::vector<std::vector<Sum>> sums;
  std::vector<double> stage_rms;
  for (const TrialFit& fit : evaluation.fits) {
    std::vector<Sum> s(fit.stages.size());
    for (Eigen::Index i = 0; i < fit.residuals_m.size(); ++i) {
      const int stage = fit.residual_blocks[i] / 4;  // block = stage * 4 + quarter
      if (stage < 0 || static_cast<std::size_t>(stage) >= s.size()) continue;
      s[stage].squares += fit.residuals_m(i) * fit.residuals_m(i);
      ++s[stage].count;
    }
    for (const Sum& x : s) {
      if (x.count > 0) stage_rms.push_back(std::sqrt(x.squares / x.count));
    }
    sums.push_back(std::move(s));
    out.weights.emplace_back(fit.stages.size(), 1.0);
  }
  if (stage_rms.size() < 3) return out;
  std::nth_element(stage_rms.begin(), stage_rms.begin() + stage_rms.size() / 2, stage_rms.end());
  out.median_rms_m = stage_rms[stage_rms.size() / 2];
  if (!(out.median_rms_m > 0.0)) return out;
  for (std::size_t t = 0; t < sums.size(); ++t) {
    for (std::size_t s = 0; s < sums[t].size(); ++s) {
      if (sums[t][s].count == 0) continue;
      const double rms = std::sqrt(sums[t][s].squares / sums[t][s].count);
      const double r = rms / out.median_rms_m;
      if (!(r > ratio)) continue;
      const double w = (ratio / r) * (ratio / r);
      out.weights[t][s] = w;
      out.outliers.push_back({t < trial_names.size() ? trial_names[t] : std::to_string(t),
                              evaluation.fits[t].stages[s].id, rms, r, w});
    }
  }
  return out;
}

}  // namespace twin::diagnosis
