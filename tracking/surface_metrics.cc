// Coverage and prediction error (stage 5).
#include "tracking/surface_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tracking {

Coverage compute_coverage(const std::vector<Vec3>& vertices_m,
                          const std::vector<Eigen::Vector3i>& triangles, const PointIndex& cloud,
                          const CoverageOptions& options) {
  Coverage c;
  const int n = static_cast<int>(vertices_m.size());
  c.covered.assign(n, 0);
  const std::vector<double> area = vertex_areas(vertices_m, triangles);
  std::vector<Eigen::Vector3f> query(n);
  for (int i = 0; i < n; ++i) query[i] = vertices_m[i].cast<float>();
  std::vector<int> counts;
  cloud.count_within(query, static_cast<float>(options.radius_m), options.min_points, counts);
  for (int i = 0; i < n; ++i) c.covered[i] = counts[i] >= options.min_points;
  double seen = 0.0, total = 0.0;
  for (int i = 0; i < n; ++i) {
    total += area[i];
    if (c.covered[i]) seen += area[i];
  }
  c.fraction = total > 0.0 ? seen / total : 0.0;
  return c;
}

PredictionError compute_prediction_error(const std::vector<Eigen::Vector3f>& observed_m,
                                         const std::vector<Vec3>& predicted_m,
                                         const std::vector<Eigen::Vector3i>& triangles,
                                         const std::vector<Vec3>& tracked_m) {
  PredictionError e = observed_against_prediction(observed_m, predicted_m, triangles);
  add_vertex_error(e, predicted_m, tracked_m);
  return e;
}

void add_vertex_error(PredictionError& e, const std::vector<Vec3>& predicted_m,
                      const std::vector<Vec3>& tracked_m) {
  const std::size_t n = std::min(predicted_m.size(), tracked_m.size());
  e.per_vertex_m.resize(n);
  e.per_vertex_norm_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    e.per_vertex_m[i] = tracked_m[i] - predicted_m[i];
    e.per_vertex_norm_m[i] = e.per_vertex_m[i].norm();
  }
}

PredictionError observed_against_prediction(const std::vector<Eigen::Vector3f>& observed_m,
                                            const std::vector<Vec3>& predicted_m,
                                            const std::vector<Eigen::Vector3i>& triangles,
                                            int threads) {
  PredictionError e;
  if (observed_m.empty() || predicted_m.empty()) return e;
  std::vector<Eigen::Vector3f> predicted(predicted_m.size());
  for (std::size_t i = 0; i < predicted_m.size(); ++i) predicted[i] = predicted_m[i].cast<float>();
  PointIndex index;
  index.build(predicted, threads);
  const int m = static_cast<int>(observed_m.size());
  std::vector<int> nearest;
  std::vector<float> d2;
  index.nearest(observed_m, std::numeric_limits<float>::infinity(), nearest, d2);
  const std::vector<std::vector<int>> around =
      vertex_triangles(static_cast<int>(predicted_m.size()), triangles);
  double sum = 0.0, worst = 0.0, surface_sum = 0.0, surface_worst = 0.0;
  for (int k = 0; k < m; ++k) {
    const double d = std::sqrt(static_cast<double>(d2[k]));
    sum += d;
    worst = std::max(worst, d);
    const Vec3 p = observed_m[k].cast<double>();
    double ds = d;
    for (int f : around[nearest[k]]) {
      const Eigen::Vector3i& t = triangles[f];
      const Vec3 q = closest_point_on_triangle(p, predicted_m[t[0]], predicted_m[t[1]], predicted_m[t[2]]);
      ds = std::min(ds, (p - q).norm());
    }
    surface_sum += ds;
    surface_worst = std::max(surface_worst, ds);
  }
  e.points = m;
  e.mean_m = sum / m;
  e.max_m = worst;
  e.score_m = e.mean_m + 0.5 * e.max_m;
  e.surface_mean_m = surface_sum / m;
  e.surface_max_m = surface_worst;
  return e;
}

}  // namespace tracking
