#pragma once
// For display only (not part of the tracking cycle): a triangle mesh reconstructed from the
// sheet's cloud by PCL (normals by NormalEstimationOMP, then GreedyProjectionTriangulation), and
// a PLY writer for it and for the tracked surface.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tracking/surface_mesh.h"

namespace tracking {

struct ReconstructionOptions {
  int normal_neighbours = 12;
  double search_radius_m = 0.03;  // longest triangle edge GP3 may make
  double neighbour_factor = 2.5;  // GP3's mu: edge limit relative to the local point spacing
  int max_neighbours = 60;
  int threads = 0;  // normal estimation; 0 = OpenMP default
};

// Empty mesh for fewer than 3 points. Never throws on data; ~0.1 s for 20k points.
SurfaceMesh reconstruct_surface(const std::vector<Eigen::Vector3f>& points_m,
                                const ReconstructionOptions& options);

// ASCII PLY (vertices in m, faces), written durably (common/durable_file.h). Throws
// std::runtime_error naming the path when it cannot be written.
void write_ply(const std::string& path, const SurfaceMesh& mesh);

}  // namespace tracking
