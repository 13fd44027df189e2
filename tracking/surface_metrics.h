#pragma once
// Stage 5 of the tracker: what the cycle tells the cell. Coverage: which part of the sheet the
// cameras saw. Prediction error: how far the twin's prediction is from what was seen, in the
// paper's Algorithm 1 form (each observed point against its nearest predicted vertex) and per
// vertex (tracked minus predicted).

#include <cstdint>
#include <vector>

#include "tracking/point_index.h"
#include "tracking/surface_mesh.h"

namespace tracking {

struct CoverageOptions {
  double radius_m = 0.012;  // a vertex is seen when at least min_points cloud points lie this close
  int min_points = 3;
};

struct Coverage {
  double fraction = 0.0;              // seen area / sheet area (tracked surface)
  std::vector<std::uint8_t> covered;  // per vertex
};

Coverage compute_coverage(const std::vector<Vec3>& vertices_m,
                          const std::vector<Eigen::Vector3i>& triangles, const PointIndex& cloud,
                          const CoverageOptions& options);

struct PredictionError {
  // Algorithm 1: for each observed point, the distance to the nearest predicted vertex (m).
  double mean_m = 0.0;
  double max_m = 0.0;
  double score_m = 0.0;  // mean + 0.5 max, the paper's single figure
  int points = 0;
  // Each observed point against the predicted SURFACE (nearest point on the triangles around
  // its nearest vertex), m. Algorithm 1 measures to vertices, so on a mesh with edges of a few
  // cm it reads about a third of an edge even for a perfect prediction; this one does not.
  double surface_mean_m = 0.0;
  double surface_max_m = 0.0;
  // Per vertex: tracked minus predicted (m) and its length.
  std::vector<Vec3> per_vertex_m;
  std::vector<double> per_vertex_norm_m;
};

PredictionError compute_prediction_error(const std::vector<Eigen::Vector3f>& observed_m,
                                         const std::vector<Vec3>& predicted_m,
                                         const std::vector<Eigen::Vector3i>& triangles,
                                         const std::vector<Vec3>& tracked_m);

// The two halves of compute_prediction_error. The first needs only the observed points and the
// prediction, so the tracker runs it beside the registration: the Algorithm 1 and surface
// figures (per_vertex left empty), its nearest-vertex searches on `threads` threads (0: OpenMP's
// default). The second fills per_vertex from the tracked surface.
PredictionError observed_against_prediction(const std::vector<Eigen::Vector3f>& observed_m,
                                            const std::vector<Vec3>& predicted_m,
                                            const std::vector<Eigen::Vector3i>& triangles,
                                            int threads = 0);
void add_vertex_error(PredictionError& error, const std::vector<Vec3>& predicted_m,
                      const std::vector<Vec3>& tracked_m);

}  // namespace tracking
