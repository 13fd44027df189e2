#pragma once
// The cell's per-cycle prediction error (PREDICTION_ERROR): the tracker's per-vertex error
// (compute_prediction_error's per_vertex_norm_m, tracked minus predicted) summarised over the
// vertices the cameras saw this cycle. Shared by whatever publishes the error and by whatever
// checks it (the monitor, log replay), so both compute exactly the same figures.

#include <cstdint>
#include <vector>

namespace tracking {

struct VertexErrorStats {
  int compared = 0;  // observed vertices with a finite error
  double mean_m = 0.0;
  double max_m = 0.0;
  double score_m = 0.0;  // mean + 0.5 max, as in PredictionError
};

// per_vertex_norm_m: one distance per vertex (m). observed: empty (every vertex counts) or one
// flag per vertex. Non-finite distances are skipped. Returns zeros when nothing is compared.
VertexErrorStats summarize_vertex_error(const std::vector<double>& per_vertex_norm_m,
                                        const std::vector<std::uint8_t>& observed);

}  // namespace tracking
