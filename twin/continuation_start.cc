#include "twin/continuation_start.h"

#include <cmath>

namespace twin {

std::optional<std::size_t> continuation_start(const std::vector<EvaluatedMaterial>& evaluated,
                                              const Eigen::VectorXd& target, double one_step, double reach) {
  std::optional<std::size_t> nearest, best_within_step;
  double nearest_distance = reach;
  for (std::size_t i = 0; i < evaluated.size(); ++i) {
    const EvaluatedMaterial& e = evaluated[i];
    if (e.coordinates.size() != target.size()) continue;
    const double d = (e.coordinates - target).cwiseAbs().maxCoeff();
    if (d <= one_step && (!best_within_step || e.sum_squares_m2 < evaluated[*best_within_step].sum_squares_m2)) {
      best_within_step = i;
    }
    bool better = d <= nearest_distance;
    if (nearest) {
      const bool tie = std::abs(d - nearest_distance) <= 1e-12;
      better = tie ? e.sum_squares_m2 < evaluated[*nearest].sum_squares_m2 : d < nearest_distance;
    }
    if (better) {
      nearest_distance = d;
      nearest = i;
    }
  }
  return best_within_step ? best_within_step : nearest;
}

}  // namespace twin
