#pragma once
// Nearest-neighbour queries on a fixed point set: the kd-tree PCL uses (FLANN's single-index
// kd-tree) behind a small interface, so registration, coverage, prediction error and the
// calibration check share one index type without including PCL or FLANN headers.
//
// Queries come in batches: FLANN opens an OpenMP region per search call, so one call per batch
// (spread over `threads`) costs far less than one call per point (measured: per-point calls
// inside our own parallel loops spent more time in thread hand-offs than in the search).

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

  // Builds the tree over `points_m` (copied). Points must be finite. `threads` = 0: OpenMP's
  // default.
  void build(const std::vector<Eigen::Vector3f>& points_m, int threads = 0);
  std::size_t size() const;
  const Eigen::Vector3f& point(int i) const;

  // For each query, the index of the nearest point (-1 when farther than max_distance_m or the
  // set is empty) and its squared distance (m^2).
  void nearest(const std::vector<Eigen::Vector3f>& queries, float max_distance_m,
               std::vector<int>& index, std::vector<float>& squared_distance) const;
  // For each query, the number of points within radius_m, counting at most `enough`.
  void count_within(const std::vector<Eigen::Vector3f>& queries, float radius_m, int enough,
                    std::vector<int>& counts) const;
  // Indices of the points within radius_m of one query.
  void within(const Eigen::Vector3f& q, float radius_m, std::vector<int>& indices) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tracking
