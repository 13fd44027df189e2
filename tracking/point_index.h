#pragma once
// Nearest-neighbour queries on a fixed point set (a PCL kd-tree behind a small interface), so
// registration, coverage, prediction error and the calibration check share one index type
// without including PCL headers.

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace tracking {

class PointIndex {
 public:
  PointIndex();
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;

  // Builds the tree over `points_m` (copied). Points must be finite.
  void build(const std::vector<Eigen::Vector3f>& points_m);
  std::size_t size() const;
  const Eigen::Vector3f& point(int i) const;

  // Index of the point nearest `q` and its squared distance (m^2); -1 when the set is empty or
  // the nearest is farther than max_distance_m.
  int nearest(const Eigen::Vector3f& q, float max_distance_m, float* squared_distance) const;
  // Number of points within radius_m of q, stopping at `enough` (0 = count all).
  int count_within(const Eigen::Vector3f& q, float radius_m, int enough) const;
  // Indices of the points within radius_m of q.
  void within(const Eigen::Vector3f& q, float radius_m, std::vector<int>& indices) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tracking
