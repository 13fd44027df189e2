// Summary of the per-vertex prediction error over the observed vertices.
#include "tracking/vertex_error.h"

#include <algorithm>
#include <cmath>

namespace tracking {

VertexErrorStats summarize_vertex_error(const std::vector<double>& per_vertex_norm_m,
                                        const std::vector<std::uint8_t>& observed) {
  VertexErrorStats s;
  const bool all = observed.empty();
  double sum = 0.0;
  for (std::size_t i = 0; i < per_vertex_norm_m.size(); ++i) {
    if (!all && (i >= observed.size() || !observed[i])) continue;
    const double d = per_vertex_norm_m[i];
    if (!std::isfinite(d)) continue;
    sum += d;
    s.max_m = std::max(s.max_m, d);
    ++s.compared;
  }
  if (s.compared == 0) return VertexErrorStats{};
  s.mean_m = sum / s.compared;
  s.score_m = s.mean_m + 0.5 * s.max_m;
  return s;
}

}  // namespace tracking
