#pragma once
// Raw laser scan of a marked sheet -> one position per marker, matched to the manifest.
//
// Scan model (the simulated scanner lab makes its scans the same way, so the two agree):
//  - Each marker is a hemispherical dome of radius r (default 3.175 mm, a quarter-inch
//    diameter) standing on the sheet's scanned side. The marker's position is the centre of
//    the dome's base, which lies on the sheet surface.
//  - The scanner returns points on the dome surfaces only (the sheet between markers is not in
//    the scan): roughly uniform over the dome's area (about 300 points for a whole dome), only
//    where the dome's outward surface normal faces the scanner, each moved by isotropic Gaussian
//    noise of 0.1-0.2 mm standard deviation.
//  - A few stray points (outliers) are scattered through the scanned volume.
//  - Markers are centimetres apart, far more than the clustering tolerance, and the dome of one
//    marker is not hidden behind another.
//
// Method: Euclidean clustering (PCL, kd-tree) of the points; clusters too small (stray points),
// too large, or wider than a marker are rejected and counted; each remaining cluster becomes a
// candidate at the centre of the least-squares sphere of radius r through its points (see
// dome_fit.h for why the sphere fit and not "centroid - r/2 n"). Candidates are then assigned to
// manifest markers near their guide positions by an optimal one-to-one assignment.

#include <optional>
#include <vector>

#include "tracking/types.h"

namespace tracking {

enum class MarkerPositionMethod {
  sphere_fit,       // centre of the known-radius sphere fitted to the cluster (default)
  centroid_offset,  // centroid - (r/2) n, n the cluster's bulge direction (kept for comparison)
};

struct MarkerExtractionOptions {
  // Largest gap between neighbouring points of one marker. A whole dome's ~300 points cover
  // 2 pi r^2 = 63 mm^2, about 0.5 mm apart, and noise moves them 0.1-0.2 mm; 1.5 mm joins each
  // dome into one cluster with margin, while markers are centimetres apart.
  double cluster_tolerance_m = 1.5e-3;
  // A scanner far from the dome (compared with r) sees at least half of it from any side it sees
  // it from at all (150 of ~300 points; 30 leaves room for a sparser scan); stray points come
  // alone or in pairs.
  int min_points = 30;
  // Far more than one dome gives; a bigger cluster is something else (sheet, clamp, a hand).
  int max_points = 5000;
  double marker_radius_m = 3.175e-3;
  // A cluster with a point farther than max_extent_radii * r from its centroid is not one marker.
  // The farthest visible point of a dome is 1.12 r from the centroid seen head-on and 1.22 r
  // seen edge-on; a stray point joined at the clustering tolerance adds at most 0.47 r.
  double max_extent_radii = 2.0;
  // A cluster whose points stray more than this (RMS) from the fitted sphere is not a dome.
  double max_fit_rms_m = 1.0e-3;
  // Scanner position (m, world). Optional: it only seeds the sphere fit from the side the
  // scanner saw; without it the cluster's own shape says which way the dome bulges.
  std::optional<Vec3> viewpoint_m;
  // Matching gate: a candidate farther than this from a marker's guide position cannot be that
  // marker. Below half the grid spacing (58 mm for 17 rows on 0.975 m), so the gates of
  // neighbouring markers do not overlap while the guides are right, and wide enough for a twin
  // prediction a couple of centimetres off.
  double gate_m = 0.025;
  MarkerPositionMethod method = MarkerPositionMethod::sphere_fit;
};

struct MarkerCandidate {
  Vec3 position_m = Vec3::Zero();  // centre of the dome's base, on the sheet surface
  Vec3 centroid_m = Vec3::Zero();  // mean of the cluster's points
  int point_count = 0;             // points in the cluster
  int kept_points = 0;             // points the sphere fit kept (stray points trimmed)
  double fit_rms_m = 0.0;          // RMS distance of the kept points from the fitted sphere
};

// Why clusters were not turned into candidates (counts of clusters, except the point counts).
struct MarkerExtractionReport {
  int scan_points = 0;
  int non_finite_points = 0;  // NaN / infinite points, skipped before clustering
  int clusters = 0;           // all clusters, single stray points included
  int too_few_points = 0;     // < min_points (stray points, scraps)
  int too_many_points = 0;    // > max_points
  int too_wide = 0;           // extent beyond max_extent_radii * r
  int bad_fit = 0;            // sphere fit did not converge, RMS above max_fit_rms_m, or centre
                              // more than r from the centroid (not a dome)
  int candidates = 0;
  int rejected() const { return too_few_points + too_many_points + too_wide + bad_fit; }
};

// Clusters the scan and returns one candidate per accepted cluster, in no particular order.
// Fills `report` when given. Throws std::invalid_argument for options that make no sense
// (non-positive radius, tolerance or gate, min_points > max_points).
std::vector<MarkerCandidate> extract_marker_candidates(const std::vector<Vec3>& scan_m,
                                                       const MarkerExtractionOptions& options,
                                                       MarkerExtractionReport* report = nullptr);

struct MarkerMatch {
  // Per manifest marker, in manifest order: the matched candidate's position (m), or NaN.
  std::vector<Vec3> positions_m;
  std::vector<int> candidate_of_marker;   // index into the candidates, -1 when unmatched
  std::vector<int> unmatched_candidates;  // indices of candidates no marker took
  int matched_count = 0;
};

// Assigns candidates to manifest markers. `guide_m` has one approximate position per manifest
// marker (a twin prediction, the previous stage's result); a NaN guide means no guess, and that
// marker stays unmatched. Pairs farther apart than `gate_m` are not allowed; among the allowed
// one-to-one assignments the one with the most pairs and then the least sum of squared
// distances is chosen (squared, because that is the most likely assignment when guide errors are
// Gaussian). Throws std::invalid_argument for a non-positive or non-finite gate.
MarkerMatch match_markers_to_manifest(const std::vector<MarkerCandidate>& candidates,
                                      const std::vector<Vec3>& guide_m, double gate_m);

}  // namespace tracking
