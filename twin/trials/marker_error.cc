#include "twin/trials/marker_error.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace twin {
namespace {

void summarise(StageError& e) {
  double sum = 0.0;
  for (double d : e.per_point_m) {
    if (std::isnan(d)) continue;
    ++e.points_used;
    sum += d;
    e.max_m = std::max(e.max_m, d);
  }
  e.mean_m = e.points_used > 0 ? sum / e.points_used : std::numeric_limits<double>::quiet_NaN();
  if (e.points_used == 0) e.max_m = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::vector<int> nearest_vertices(const std::vector<Vec3>& observed_m, const VecX& x_predicted_m) {
  std::vector<int> nearest(observed_m.size(), -1);
  const Eigen::Index n = x_predicted_m.size() / 3;
  // Brute force: a few hundred markers times a few thousand vertices is about a millisecond,
  // and the twin library stays free of spatial-index dependencies.
  for (std::size_t i = 0; i < observed_m.size(); ++i) {
    if (!observed_m[i].allFinite()) continue;
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index v = 0; v < n; ++v) {
      const double d2 = (x_predicted_m.segment<3>(3 * v) - observed_m[i]).squaredNorm();
      if (d2 < best) {
        best = d2;
        nearest[i] = static_cast<int>(v);
      }
    }
  }
  return nearest;
}

StageError nearest_vertex_error(const std::vector<Vec3>& observed_m, const VecX& x_predicted_m) {
  StageError e;
  e.per_point_m.assign(observed_m.size(), std::numeric_limits<double>::quiet_NaN());
  const std::vector<int> nearest = nearest_vertices(observed_m, x_predicted_m);
  for (std::size_t i = 0; i < observed_m.size(); ++i) {
    if (nearest[i] >= 0) e.per_point_m[i] = (x_predicted_m.segment<3>(3 * nearest[i]) - observed_m[i]).norm();
  }
  summarise(e);
  return e;
}

StageError correspondence_error(const std::vector<Vec3>& observed_m,
                                const std::vector<Vec3>& predicted_m) {
  if (observed_m.size() != predicted_m.size()) {
    throw std::invalid_argument(fmt::format("correspondence error: {} observed markers but {} predicted",
                                            observed_m.size(), predicted_m.size()));
  }
  StageError e;
  e.per_point_m.assign(observed_m.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < observed_m.size(); ++i) {
    if (observed_m[i].allFinite()) e.per_point_m[i] = (observed_m[i] - predicted_m[i]).norm();
  }
  summarise(e);
  return e;
}

}  // namespace twin
