// FLANN kd-tree (PCL's search back-end) behind PointIndex, queried in batches.
#include "tracking/point_index.h"

#include <omp.h>
#include <flann/flann.hpp>

#include <limits>

namespace tracking {

struct PointIndex::Impl {
  std::vector<Eigen::Vector3f> points;
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> tree;
  int threads = 1;

  flann::SearchParams params() const {
    flann::SearchParams p(-1, 0.0f, false);  // exact search, results unsorted
    p.cores = threads;
    return p;
  }
};

namespace {

// Eigen::Vector3f is three packed floats, so a vector of them is an n x 3 row-major matrix.
flann::Matrix<float> as_matrix(const std::vector<Eigen::Vector3f>& points) {
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
  return flann::Matrix<float>(const_cast<float*>(points.data()->data()), points.size(), 3);
}

}  // namespace

PointIndex::PointIndex() : impl_(std::make_unique<Impl>()) {}
PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

void PointIndex::build(const std::vector<Eigen::Vector3f>& points_m, int threads) {
  impl_->points = points_m;
  impl_->threads = threads > 0 ? threads : omp_get_max_threads();
  impl_->tree.reset();
  if (points_m.empty()) return;  // queries on an empty index answer "nothing"
  impl_->tree = std::make_unique<flann::Index<flann::L2_Simple<float>>>(
      as_matrix(impl_->points), flann::KDTreeSingleIndexParams(15));
  impl_->tree->buildIndex();
}

std::size_t PointIndex::size() const { return impl_->points.size(); }

const Eigen::Vector3f& PointIndex::point(int i) const { return impl_->points[i]; }

void PointIndex::nearest(const std::vector<Eigen::Vector3f>& queries, float max_distance_m,
                         std::vector<int>& index, std::vector<float>& squared_distance) const {
  index.assign(queries.size(), -1);
  squared_distance.assign(queries.size(), std::numeric_limits<float>::infinity());
  if (!impl_->tree || queries.empty()) return;
  flann::Matrix<int> idx(index.data(), queries.size(), 1);
  flann::Matrix<float> d2(squared_distance.data(), queries.size(), 1);
  // The nearest point within the gate (FLANN's k-nearest-within-radius result set with k = 1):
  // the search prunes every branch farther than the gate from the start, where an unbounded
  // nearest-neighbour search first walks to the nearest point however far it is (a vertex the
  // cameras do not see, say) and the gate is applied after. Same answer.
  flann::SearchParams p = impl_->params();
  p.max_neighbors = 1;
  const float limit = max_distance_m * max_distance_m;
  impl_->tree->radiusSearch(as_matrix(queries), idx, d2, limit, p);
  for (std::size_t k = 0; k < queries.size(); ++k) {
    if (!(squared_distance[k] <= limit)) {
      index[k] = -1;
      squared_distance[k] = std::numeric_limits<float>::infinity();
    }
  }
}

void PointIndex::count_within(const std::vector<Eigen::Vector3f>& queries, float radius_m,
                              int enough, std::vector<int>& counts) const {
  counts.assign(queries.size(), 0);
  if (!impl_->tree || queries.empty()) return;
  std::vector<std::vector<int>> found;
  std::vector<std::vector<float>> d2;
  flann::SearchParams p = impl_->params();
  p.max_neighbors = enough > 0 ? enough : -1;
  impl_->tree->radiusSearch(as_matrix(queries), found, d2, radius_m * radius_m, p);
  for (std::size_t k = 0; k < queries.size(); ++k) counts[k] = static_cast<int>(found[k].size());
}

void PointIndex::within(const Eigen::Vector3f& q, float radius_m, std::vector<int>& indices) const {
  indices.clear();
  if (!impl_->tree) return;
  std::vector<std::vector<int>> found;
  std::vector<std::vector<float>> d2;
  flann::SearchParams p = impl_->params();
  p.cores = 1;  // one query: no thread team
  const std::vector<Eigen::Vector3f> one{q};
  impl_->tree->radiusSearch(as_matrix(one), found, d2, radius_m * radius_m, p);
  indices = std::move(found[0]);
}

}  // namespace tracking
