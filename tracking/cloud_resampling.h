#pragma once
// Stage 3 of the tracker: voxel resampling (PCL VoxelGrid: one point per occupied voxel, the
// centroid of its points, which also averages the depth noise) and optional statistical outlier
// removal (PCL StatisticalOutlierRemoval: flying pixels at depth edges). PCL stays in the .cc.

#include <vector>

#include <Eigen/Core>

namespace tracking {

struct ResampleOptions {
  // 10 mm: a few points per voxel from each camera at 1.5 m; the registration's smoothing (4 cm)
  // averages far more than one voxel, so finer voxels cost time (kd-tree, queries) for nothing
  // (tracker_benchmark at 848x480: 8 mm and 10 mm track within 0.05 mm of each other, mean
  // 0.35 vs 0.39 mm, and 10 mm saves ~8 ms of a ~42 ms cycle). Coarser than ~12 mm leaves too few
  // points within the coverage radius (12 mm, 3 points).
  double voxel_m = 0.010;
  // pcl::ApproximateVoxelGrid (hashing, no sort) instead of pcl::VoxelGrid. Off: measured slower
  // overall, since hash collisions split voxels and the later stages get ~1.5x more points.
  bool approximate = false;
  bool remove_outliers = false;  // costs about as much as the voxel grid; off by default
  int outlier_neighbours = 12;
  double outlier_stddev = 2.0;  // points whose mean neighbour distance is beyond mean + k sigma
};

// Voxel centroids (and outlier removal when enabled). Points must be finite.
std::vector<Eigen::Vector3f> resample_cloud(const std::vector<Eigen::Vector3f>& points_m,
                                            const ResampleOptions& options);

}  // namespace tracking
