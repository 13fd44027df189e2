#pragma once
// Where a scanned marker dome sits: the centre of its base, from the dome's surface points.
// Scan model: see marker_extraction.h.
//
// Two estimators, both here so the tests can compare them:
//  - fit_dome_sphere: least-squares sphere of the known radius r; the sphere's centre is the
//    centre of the dome's base (the dome is a hemisphere). This is the one extract_markers uses.
//  - dome_centroid_offset: centroid - (r/2) n. Exact only on average and only when the whole
//    hemisphere is sampled uniformly (mean height of area-uniform points is r/2).
// Why the sphere fit wins (measured in tests/tracking/marker_extraction_test.cc): the centroid
// carries the sampling randomness of *where* on the dome the points fell (standard deviation
// of area-uniform points is about 0.58 r sideways and 0.29 r in height, i.e. ~0.1 mm for 300
// points), needs a sheet normal that a dome patch does not give reliably, and is biased when
// the scanner sees the dome obliquely and part of it is hidden (the visible part's mean is not
// r/2 above the base). The sphere fit only carries the surface noise (~sigma / sqrt(N / 3)),
// needs no normal, and does not care which part of the dome was seen.

#include <optional>
#include <vector>

#include "tracking/types.h"

namespace tracking {

struct DomeFit {
  Vec3 base_centre_m = Vec3::Zero();
  double rms_m = 0.0;       // RMS distance of the kept points from the fitted sphere
  int kept_points = 0;      // points left after trimming gross outliers
  int iterations = 0;       // Gauss-Newton iterations, all rounds together
  bool converged = false;   // the last round's steps fell below 1e-9 m
};

// Unit vector along the cluster's smallest spread (its principal axis of least variance), with
// the sign chosen so that the dome bulges toward it: the points farthest from the axis (the
// rim) lie lowest along it. For a whole hemisphere this is the sheet normal on the scanned side;
// for a partly hidden dome it tilts toward the visible part, so it is only a starting guess.
Vec3 dome_bulge_direction(const std::vector<Vec3>& points_m);

// Gauss-Newton fit of a sphere of radius `radius_m` to the points, started at each of the given
// centres (the best result by RMS is kept, so a start on the wrong side of the dome does not
// matter as long as one start is on the concave side). After convergence, points farther than
// max(4 robust sigmas, 0.02 r) from the sphere are dropped and the fit repeated (up to three
// rounds), so a stray point that joined the cluster does not pull the centre. Needs >= 4
// points; returns converged = false otherwise.
DomeFit fit_dome_sphere(const std::vector<Vec3>& points_m, double radius_m,
                        const std::vector<Vec3>& start_centres_m);

// The mean of `points_m` (not empty).
Vec3 centroid_of(const std::vector<Vec3>& points_m);

// centroid - (radius / 2) * normal, with `normal` the unit sheet normal toward the scanner.
Vec3 dome_centroid_offset(const std::vector<Vec3>& points_m, double radius_m, const Vec3& normal);

}  // namespace tracking
