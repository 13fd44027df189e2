// Recomputed prediction error and distance to the true sheet.
#include "cell/sheet_comparison.h"

#include <cmath>
#include <limits>

#include "tracking/point_index.h"
#include "tracking/surface_metrics.h"
#include "tracking/vertex_error.h"

namespace cell {

namespace {

std::vector<tracking::Vec3> vertices(const prepreg_lcm::sheet_state_t& s) {
  std::vector<tracking::Vec3> v(static_cast<std::size_t>(s.num_vertices));
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = {s.x_m[i], s.y_m[i], s.z_m[i]};
  return v;
}

}  // namespace

std::optional<ErrorFigures> recompute_prediction_error(
    const prepreg_lcm::sheet_state_t& observed, const prepreg_lcm::sheet_state_t& predicted) {
  if (observed.num_vertices != predicted.num_vertices || observed.num_vertices == 0) {
    return std::nullopt;
  }
  // No observed cloud in the log: only the per-vertex part of the tracker's metric applies.
  const tracking::PredictionError e =
      tracking::compute_prediction_error({}, vertices(predicted), {}, vertices(observed));
  std::vector<std::uint8_t> flags(observed.vertex_observed.begin(), observed.vertex_observed.end());
  const tracking::VertexErrorStats s = tracking::summarize_vertex_error(e.per_vertex_norm_m, flags);
  return ErrorFigures{s.compared, s.mean_m, s.max_m, s.score_m};
}

std::vector<Eigen::Vector3f> sheet_points(const prepreg_lcm::sheet_state_t& s, bool observed_only) {
  std::vector<Eigen::Vector3f> p;
  p.reserve(static_cast<std::size_t>(s.num_vertices));
  const bool flags = observed_only && s.num_observed_flags == s.num_vertices;
  for (int i = 0; i < s.num_vertices; ++i) {
    if (flags && !s.vertex_observed[i]) continue;
    p.emplace_back(s.x_m[i], s.y_m[i], s.z_m[i]);
  }
  return p;
}

std::optional<double> mean_nearest_distance_m(const std::vector<Eigen::Vector3f>& points,
                                              const tracking::PointIndex& truth) {
  if (points.empty() || truth.size() == 0) return std::nullopt;
  std::vector<int> nearest;
  std::vector<float> d2;
  truth.nearest(points, std::numeric_limits<float>::infinity(), nearest, d2);
  double sum = 0.0;
  for (float d : d2) sum += std::sqrt(static_cast<double>(d));
  return sum / static_cast<double>(points.size());
}

}  // namespace cell
