// PCL surface reconstruction for display, and PLY output.
#include "tracking/cloud_surface.h"

#include <pcl/common/io.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "common/durable_file.h"

namespace tracking {

SurfaceMesh reconstruct_surface(const std::vector<Eigen::Vector3f>& points_m,
                                const ReconstructionOptions& options) {
  SurfaceMesh mesh;
  if (points_m.size() < 3) return mesh;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(points_m.size());
  for (std::size_t i = 0; i < points_m.size(); ++i) (*cloud)[i].getVector3fMap() = points_m[i];

  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(cloud);
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> normals;
  normals.setNumberOfThreads(options.threads > 0 ? options.threads : 0);
  normals.setInputCloud(cloud);
  normals.setSearchMethod(tree);
  normals.setKSearch(options.normal_neighbours);
  pcl::PointCloud<pcl::Normal> normal_cloud;
  normals.compute(normal_cloud);

  pcl::PointCloud<pcl::PointNormal>::Ptr oriented(new pcl::PointCloud<pcl::PointNormal>);
  pcl::concatenateFields(*cloud, normal_cloud, *oriented);
  // Points whose neighbourhood was degenerate get NaN normals; GP3 cannot use them.
  pcl::PointCloud<pcl::PointNormal>::Ptr usable(new pcl::PointCloud<pcl::PointNormal>);
  for (const pcl::PointNormal& p : *oriented) {
    if (std::isfinite(p.normal_x) && std::isfinite(p.normal_y) && std::isfinite(p.normal_z)) {
      usable->push_back(p);
    }
  }
  if (usable->size() < 3) return mesh;
  pcl::search::KdTree<pcl::PointNormal>::Ptr tree2(new pcl::search::KdTree<pcl::PointNormal>);
  tree2->setInputCloud(usable);
  pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
  gp3.setSearchRadius(options.search_radius_m);
  gp3.setMu(options.neighbour_factor);
  gp3.setMaximumNearestNeighbors(options.max_neighbours);
  gp3.setMaximumSurfaceAngle(M_PI / 4);
  gp3.setMinimumAngle(M_PI / 18);
  gp3.setMaximumAngle(2 * M_PI / 3);
  gp3.setNormalConsistency(false);
  gp3.setInputCloud(usable);
  gp3.setSearchMethod(tree2);
  std::vector<pcl::Vertices> polygons;
  gp3.reconstruct(polygons);

  mesh.vertices_m.reserve(usable->size());
  for (const pcl::PointNormal& p : *usable) mesh.vertices_m.emplace_back(p.x, p.y, p.z);
  for (const pcl::Vertices& poly : polygons) {
    if (poly.vertices.size() != 3) continue;
    mesh.triangles.emplace_back(poly.vertices[0], poly.vertices[1], poly.vertices[2]);
  }
  return mesh;
}

void write_ply(const std::string& path, const SurfaceMesh& mesh) {
  prepreg::write_file_atomically(path, [&](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment units: metres, cell frame\n"
        << "element vertex " << mesh.vertices_m.size() << "\nproperty float x\nproperty float y\n"
        << "property float z\nelement face " << mesh.triangles.size()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& v : mesh.vertices_m) out << fmt::format("{:.6f} {:.6f} {:.6f}\n", v.x(), v.y(), v.z());
    for (const Eigen::Vector3i& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  });
}

}  // namespace tracking
