// Clustering of the raw scan into marker candidates. The only file of the library that includes
// PCL (its headers are slow to compile), so every other file stays PCL-free.
#include "tracking/marker_extraction.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tracking/dome_fit.h"

namespace tracking {
namespace {

void check_options(const MarkerExtractionOptions& o) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!positive(o.marker_radius_m)) {
    throw std::invalid_argument("marker radius must be positive and finite (m)");
  }
  if (!positive(o.cluster_tolerance_m)) {
    throw std::invalid_argument("cluster tolerance must be positive and finite (m)");
  }
  if (!positive(o.max_extent_radii)) {
    throw std::invalid_argument("maximum cluster extent must be positive (marker radii)");
  }
  if (!positive(o.max_fit_rms_m)) {
    throw std::invalid_argument("maximum fit RMS must be positive and finite (m)");
  }
  if (o.min_points < 4 || o.max_points < o.min_points) {
    throw std::invalid_argument("need 4 <= min points per cluster <= max points per cluster");
  }
  if (o.viewpoint_m && !o.viewpoint_m->allFinite()) {
    throw std::invalid_argument("viewpoint must be finite (m)");
  }
}

// Point indices (into `scan`) of every Euclidean cluster, singletons included.
std::vector<std::vector<int>> euclidean_clusters(const std::vector<Vec3>& scan,
                                                 double tolerance_m, int& non_finite) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<int> scan_index;  // cloud point -> scan point
  cloud->reserve(scan.size());
  scan_index.reserve(scan.size());
  non_finite = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan[i].allFinite()) {
      ++non_finite;  // a kd-tree cannot hold NaN, and a NaN point says nothing anyway
      continue;
    }
    // float is PCL's point type: 0.1 um steps at 1 m, plenty for grouping points; the sphere fit
    // goes back to the double coordinates.
    cloud->push_back(pcl::PointXYZ(static_cast<float>(scan[i].x()),
                                   static_cast<float>(scan[i].y()),
                                   static_cast<float>(scan[i].z())));
    scan_index.push_back(static_cast<int>(i));
  }
  std::vector<std::vector<int>> clusters;
  if (cloud->empty()) return clusters;

  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
  extraction.setClusterTolerance(tolerance_m);
  // Every cluster is returned, whatever its size, so the size limits are applied (and counted)
  // below rather than silently inside PCL.
  extraction.setMinClusterSize(1);
  extraction.setMaxClusterSize(std::numeric_limits<pcl::uindex_t>::max());
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(cloud);
  std::vector<pcl::PointIndices> found;
  extraction.extract(found);

  clusters.reserve(found.size());
  for (const pcl::PointIndices& indices : found) {
    std::vector<int> members;
    members.reserve(indices.indices.size());
    for (const auto k : indices.indices) members.push_back(scan_index[k]);
    clusters.push_back(std::move(members));
  }
  return clusters;
}

}  // namespace

std::vector<MarkerCandidate> extract_marker_candidates(const std::vector<Vec3>& scan,
                                                       const MarkerExtractionOptions& options,
                                                       MarkerExtractionReport* report) {
  check_options(options);
  MarkerExtractionReport counts;
  counts.scan_points = static_cast<int>(scan.size());
  const std::vector<std::vector<int>> clusters =
      euclidean_clusters(scan, options.cluster_tolerance_m, counts.non_finite_points);
  counts.clusters = static_cast<int>(clusters.size());

  const double r = options.marker_radius_m;
  std::vector<MarkerCandidate> candidates;
  std::vector<Vec3> points;
  for (const std::vector<int>& members : clusters) {
    const int n = static_cast<int>(members.size());
    if (n < options.min_points) {
      ++counts.too_few_points;
      continue;
    }
    if (n > options.max_points) {
      ++counts.too_many_points;
      continue;
    }
    points.clear();
    for (const int i : members) points.push_back(scan[i]);
    const Vec3 centroid = centroid_of(points);
    double extent = 0.0;
    for (const Vec3& p : points) extent = std::max(extent, (p - centroid).norm());
    if (extent > options.max_extent_radii * r) {
      ++counts.too_wide;
      continue;
    }

    // The base centre lies about r/2 behind the centroid, on the side away from the bulge;
    // seed the fit there, and also from the scanner's side when its position is known.
    Vec3 bulge = dome_bulge_direction(points);
    std::vector<Vec3> starts{centroid - 0.5 * r * bulge};
    if (options.viewpoint_m) {
      const Vec3 toward_scanner = (*options.viewpoint_m - centroid).normalized();
      starts.push_back(centroid - 0.5 * r * toward_scanner);
      if (bulge.dot(toward_scanner) < 0.0) bulge = -bulge;  // a dome bulges toward its viewer
    }
    const DomeFit fit = fit_dome_sphere(points, r, starts);
    // The centroid of points on a sphere lies inside it, so a centre more than r away is a fit
    // that wandered off (or a cluster that is no sphere).
    if (!fit.converged || fit.rms_m > options.max_fit_rms_m ||
        (fit.base_centre_m - centroid).norm() > r) {
      ++counts.bad_fit;
      continue;
    }

    MarkerCandidate c;
    c.position_m = options.method == MarkerPositionMethod::sphere_fit
                       ? fit.base_centre_m
                       : dome_centroid_offset(points, r, bulge);
    c.centroid_m = centroid;
    c.point_count = n;
    c.kept_points = fit.kept_points;
    c.fit_rms_m = fit.rms_m;
    candidates.push_back(c);
  }
  counts.candidates = static_cast<int>(candidates.size());
  if (report) *report = counts;
  return candidates;
}

}  // namespace tracking
