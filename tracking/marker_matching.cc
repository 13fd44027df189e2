// Manifest matching of marker candidates (declared in marker_extraction.h; kept apart from the
// clustering so this file does not pay for PCL's headers).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tracking/assignment.h"
#include "tracking/marker_extraction.h"

namespace tracking {

MarkerMatch match_markers_to_manifest(const std::vector<MarkerCandidate>& candidates,
                                      const std::vector<Vec3>& guide_m, double gate_m) {
  if (!std::isfinite(gate_m) || gate_m <= 0.0) {
    throw std::invalid_argument("matching gate must be positive and finite (m)");
  }
  const int markers = static_cast<int>(guide_m.size());
  const int count = static_cast<int>(candidates.size());
  const double inf = std::numeric_limits<double>::infinity();

  // Squared distances (m^2); pairs outside the gate, and markers without a guide, forbidden.
  Eigen::MatrixXd cost(markers, count);
  for (int i = 0; i < markers; ++i) {
    for (int j = 0; j < count; ++j) {
      const double d2 = (candidates[j].position_m - guide_m[i]).squaredNorm();
      cost(i, j) = (std::isfinite(d2) && d2 <= gate_m * gate_m) ? d2 : inf;
    }
  }
  const Assignment assignment = solve_assignment(cost);

  MarkerMatch match;
  const Vec3 unknown = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  match.positions_m.assign(markers, unknown);
  match.candidate_of_marker = assignment.column_of_row;
  for (int i = 0; i < markers; ++i) {
    const int j = assignment.column_of_row[i];
    if (j >= 0) match.positions_m[i] = candidates[j].position_m;
  }
  for (int j = 0; j < count; ++j) {
    if (assignment.row_of_column[j] < 0) match.unmatched_candidates.push_back(j);
  }
  match.matched_count = assignment.assigned_count;
  return match;
}

}  // namespace tracking
