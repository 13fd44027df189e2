// Pairwise point-to-plane agreement between cameras (stage 6).
#include "tracking/calibration_check.h"

#include <pcl/common/centroid.h>
#include <pcl/common/eigen.h>

#include <algorithm>
#include <cmath>

#include "tracking/cloud_resampling.h"
#include "tracking/point_index.h"

namespace tracking {
namespace {

double percentile(std::vector<double> values, double q) {
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

std::vector<CameraPairAgreement> check_calibration(const SensorCloud& cloud, int cameras,
                                                   const CalibrationCheckOptions& options) {
  std::vector<CameraPairAgreement> pairs;
  if (!options.enabled || cameras < 2) return pairs;
  std::vector<std::vector<Eigen::Vector3f>> own(cameras);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.camera[i] < cameras) own[cloud.camera[i]].push_back(cloud.points_m[i]);
  }
  ResampleOptions voxel;
  voxel.voxel_m = options.voxel_m;
  std::vector<std::vector<Eigen::Vector3f>> averaged(cameras);
  std::vector<PointIndex> index(cameras);
  for (int c = 0; c < cameras; ++c) {
    averaged[c] = resample_cloud(own[c], voxel);
    index[c].build(averaged[c]);
  }
  for (int a = 0; a < cameras; ++a) {
    for (int b = a + 1; b < cameras; ++b) {
      CameraPairAgreement pair;
      pair.camera_a = a;
      pair.camera_b = b;
      const std::vector<Eigen::Vector3f>& pa = averaged[a];
      const std::size_t step =
          std::max<std::size_t>(1, pa.size() / std::max(options.max_points, 1));
      std::vector<double> distance;
      std::vector<int> near;
      const pcl::PointCloud<pcl::PointXYZ>::Ptr neighbours(new pcl::PointCloud<pcl::PointXYZ>);
      for (std::size_t k = 0; k < pa.size(); k += step) {
        index[b].within(pa[k], static_cast<float>(options.plane_radius_m), near);
        if (static_cast<int>(near.size()) < options.min_plane_points) continue;
        neighbours->resize(near.size());
        for (std::size_t j = 0; j < near.size(); ++j) {
          (*neighbours)[j].getVector3fMap() = index[b].point(near[j]);
        }
        Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
        Eigen::Vector4f centroid = Eigen::Vector4f::Zero();
        pcl::computeMeanAndCovarianceMatrix(*neighbours, covariance, centroid);
        float eigenvalue = 0.0f;
        Eigen::Vector3f normal;
        pcl::eigen33(covariance, eigenvalue, normal);  // smallest eigenvector: the plane normal
        distance.push_back(std::abs(normal.dot(pa[k] - centroid.head<3>())));
      }
      pair.overlap_points = static_cast<int>(distance.size());
      pair.judged = pair.overlap_points >= options.min_overlap_points;
      if (pair.judged) {
        pair.median_m = percentile(distance, 0.5);
        pair.p90_m = percentile(distance, 0.9);
        pair.flagged = pair.median_m > options.max_median_m || pair.p90_m > options.max_p90_m;
      }
      pairs.push_back(pair);
    }
  }
  return pairs;
}

}  // namespace tracking
