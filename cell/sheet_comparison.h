#pragma once
// Checks on logged/received sheet states, with the tracker's own metrics: the prediction error
// recomputed from an observed and a predicted sheet_state_t (what PREDICTION_ERROR must say),
// and the distance of a sheet to the fake world's true sheet.

#include <Eigen/Core>
#include <optional>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <vector>

#include "cell/monitor_record.h"

namespace tracking {
class PointIndex;
}

namespace cell {

// tracking::compute_prediction_error's per-vertex error (observed minus predicted) summarised
// over the observed vertices (tracking::summarize_vertex_error). Nothing when the two states
// have different vertex counts.
std::optional<ErrorFigures> recompute_prediction_error(const prepreg_lcm::sheet_state_t& observed,
                                                       const prepreg_lcm::sheet_state_t& predicted);

std::vector<Eigen::Vector3f> sheet_points(const prepreg_lcm::sheet_state_t& sheet,
                                          bool observed_only);

// Mean distance (m) from each point to its nearest point of `truth`; nothing if either is empty.
std::optional<double> mean_nearest_distance_m(const std::vector<Eigen::Vector3f>& points,
                                              const tracking::PointIndex& truth);

}  // namespace cell
