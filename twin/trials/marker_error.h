#pragma once
// How far a simulated sheet is from what was scanned, per stage (paper section 4.3).
//
// Two measures, both reported everywhere:
//  - nearest-vertex error (the paper's Algorithm 1): for each observed point, the distance to
//    the nearest vertex of the predicted mesh. Needs no correspondence, so it also scores
//    stages seen as an unordered cloud; but it cannot see sliding along the surface, and it
//    carries a floor of up to about half an edge length from the mesh's discreteness.
//  - correspondence error: each marker against the prediction of its own material point.
//    Sees sliding along the surface; needs markers.
// A stage's score is mean + w * max (the paper uses w = 0.5 in its tables, 2 in Eq. 11).

#include <vector>

#include "twin/base/types.h"

namespace twin {

struct StageError {
  int points_used = 0;           // observed points that were scored (NaN markers skipped)
  double mean_m = 0.0, max_m = 0.0;
  std::vector<double> per_point_m;  // per observed point, NaN where not seen
  double score(double max_weight) const { return mean_m + max_weight * max_m; }
};

// Algorithm 1: observed points (m; NaN rows skipped) against the vertices of x (3n, m).
StageError nearest_vertex_error(const std::vector<Vec3>& observed_m, const VecX& x_predicted_m);

// Index of the vertex of x nearest to each observed point (-1 for a NaN row): Algorithm 1's
// pairing.
std::vector<int> nearest_vertices(const std::vector<Vec3>& observed_m, const VecX& x_predicted_m);

// Each observed marker against its predicted material point (same order; NaN rows skipped).
// Throws std::invalid_argument when the counts differ.
StageError correspondence_error(const std::vector<Vec3>& observed_m,
                                const std::vector<Vec3>& predicted_m);

}  // namespace twin
