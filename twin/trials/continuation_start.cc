#include "twin/trials/continuation_start.h"

#include <cmath>

namespace twin {

ContinuationStarts continuation_starts(const std::vector<EvaluatedMaterial>& evaluated, const Eigen::VectorXd& target,
                                       double one_step, double reach) {
  ContinuationStarts out;
  std::optional<std::size_t> best_within_step;
  double nearest_distance = reach;
  for (std::size_t i = 0; i < evaluated.size(); ++i) {
    const EvaluatedMaterial& e = evaluated[i];
    if (e.coordinates.size() != target.size()) continue;
    const double d = (e.coordinates - target).cwiseAbs().maxCoeff();
    if (d <= one_step && (!best_within_step || e.sum_squares_m2 < evaluated[*best_within_step].sum_squares_m2)) {
      best_within_step = i;
    }
    bool better = d <= nearest_distance;
    if (out.nearest) {
      const bool tie = std::abs(d - nearest_distance) <= 1e-12;
      better = tie ? e.sum_squares_m2 < evaluated[*out.nearest].sum_squares_m2 : d < nearest_distance;
    }
    if (better) {
      nearest_distance = d;
      out.nearest = i;
    }
  }
  if (best_within_step != out.nearest) out.best_nearby = best_within_step;
  return out;
}

}  // namespace twin
