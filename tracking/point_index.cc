// PCL kd-tree (FLANN) behind PointIndex.
#include "tracking/point_index.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace tracking {

struct PointIndex::Impl {
  std::vector<Eigen::Vector3f> points;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
};

PointIndex::PointIndex() : impl_(std::make_unique<Impl>()) {}
PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

void PointIndex::build(const std::vector<Eigen::Vector3f>& points_m) {
  impl_->points = points_m;
  impl_->cloud.reset(new pcl::PointCloud<pcl::PointXYZ>);
  impl_->cloud->resize(points_m.size());
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    (*impl_->cloud)[i].getVector3fMap() = points_m[i];
  }
  // The tree refuses an empty cloud; queries on an empty index answer "nothing" instead.
  if (!points_m.empty()) impl_->tree.setInputCloud(impl_->cloud);
}

std::size_t PointIndex::size() const { return impl_->points.size(); }

const Eigen::Vector3f& PointIndex::point(int i) const { return impl_->points[i]; }

int PointIndex::nearest(const Eigen::Vector3f& q, float max_distance_m,
                        float* squared_distance) const {
  if (impl_->points.empty()) return -1;
  pcl::PointXYZ p;
  p.getVector3fMap() = q;
  pcl::Indices index(1);
  std::vector<float> d2(1);
  if (impl_->tree.nearestKSearch(p, 1, index, d2) < 1) return -1;
  if (d2[0] > max_distance_m * max_distance_m) return -1;
  if (squared_distance) *squared_distance = d2[0];
  return index[0];
}

int PointIndex::count_within(const Eigen::Vector3f& q, float radius_m, int enough) const {
  if (impl_->points.empty()) return 0;
  pcl::PointXYZ p;
  p.getVector3fMap() = q;
  pcl::Indices index;
  std::vector<float> d2;
  return impl_->tree.radiusSearch(p, radius_m, index, d2,
                                  enough > 0 ? static_cast<unsigned>(enough) : 0u);
}

void PointIndex::within(const Eigen::Vector3f& q, float radius_m, std::vector<int>& indices) const {
  indices.clear();
  if (impl_->points.empty()) return;
  pcl::PointXYZ p;
  p.getVector3fMap() = q;
  pcl::Indices index;
  std::vector<float> d2;
  impl_->tree.radiusSearch(p, radius_m, index, d2);
  indices.assign(index.begin(), index.end());
}

}  // namespace tracking
