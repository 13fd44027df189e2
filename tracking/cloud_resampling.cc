// Voxel grid and outlier removal through PCL (stage 3).
#include "tracking/cloud_resampling.h"

#include <pcl/filters/approximate_voxel_grid.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace tracking {

std::vector<Eigen::Vector3f> resample_cloud(const std::vector<Eigen::Vector3f>& points_m,
                                            const ResampleOptions& options) {
  std::vector<Eigen::Vector3f> out;
  if (points_m.empty()) return out;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(points_m.size());
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    (*cloud)[i].getVector3fMap() = points_m[i];
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr voxels(new pcl::PointCloud<pcl::PointXYZ>);
  const float leaf = static_cast<float>(options.voxel_m);
  if (options.voxel_m > 0.0 && options.approximate) {
    pcl::ApproximateVoxelGrid<pcl::PointXYZ> grid;
    grid.setInputCloud(cloud);
    grid.setLeafSize(leaf, leaf, leaf);
    grid.filter(*voxels);
  } else if (options.voxel_m > 0.0) {
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    grid.setInputCloud(cloud);
    grid.setLeafSize(leaf, leaf, leaf);
    grid.filter(*voxels);
  } else {
    voxels = cloud;
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr kept = voxels;
  if (options.remove_outliers &&
      voxels->size() > static_cast<std::size_t>(options.outlier_neighbours)) {
    kept.reset(new pcl::PointCloud<pcl::PointXYZ>);
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
    sor.setInputCloud(voxels);
    sor.setMeanK(options.outlier_neighbours);
    sor.setStddevMulThresh(options.outlier_stddev);
    sor.filter(*kept);
  }
  out.reserve(kept->size());
  for (const pcl::PointXYZ& p : *kept) out.push_back(p.getVector3fMap());
  return out;
}

}  // namespace tracking
