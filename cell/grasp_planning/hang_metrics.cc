#include "cell/grasp_planning/hang_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace cell {
namespace {

using twin::Vec2;
using twin::Vec3;

Vec3 triangle_normal(const twin::SheetMesh& mesh, const twin::VecX& x, int t) {
  const auto& tri = mesh.triangles[t];
  const Vec3 a = twin::vertex(x, tri[0]), b = twin::vertex(x, tri[1]), c = twin::vertex(x, tri[2]);
  return (b - a).cross(c - a).normalized();
}

// Whether the cell-frame point p (x, y) lies over the tool's top rectangle.
bool over_tool(const ToolSpec& tool, const Vec3& p) {
  if (!tool.has_size) return true;
  const Vec2 d = p.head<2>() - tool.centre_m;
  const double c = std::cos(tool.yaw_rad), s = std::sin(tool.yaw_rad);
  const Vec2 local(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  return std::abs(local.x()) <= 0.5 * tool.size_m.x() && std::abs(local.y()) <= 0.5 * tool.size_m.y();
}

}  // namespace

HangMetrics measure_hang(const twin::SheetMesh& mesh, const twin::VecX& x, double hold_z_m,
                         const ToolSpec& tool) {
  HangMetrics m;
  m.lowest_z_m = std::numeric_limits<double>::infinity();
  double lowest_over_tool = std::numeric_limits<double>::infinity();
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const Vec3 p = twin::vertex(x, i);
    m.lowest_z_m = std::min(m.lowest_z_m, p.z());
    if (over_tool(tool, p)) lowest_over_tool = std::min(lowest_over_tool, p.z());
  }
  m.sag_m = hold_z_m - m.lowest_z_m;
  m.clearance_m = lowest_over_tool - tool.top_z_m;

  std::vector<Vec3> normals(mesh.triangle_count());
  double overturned_area = 0.0;
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    normals[t] = triangle_normal(mesh, x, t);
    if (normals[t].z() < -0.5) overturned_area += mesh.rest_area(t);
  }
  m.overturned_fraction = overturned_area / mesh.total_rest_area();

  // Hinges: interior edges, each shared by two triangles.
  std::map<std::pair<int, int>, int> first_triangle;
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = first_triangle.emplace(key, t);
      if (inserted) continue;
      const double edge_m = (mesh.rest_uv[a] - mesh.rest_uv[b]).norm();
      const double heights_m = 2.0 * (mesh.rest_area(t) + mesh.rest_area(it->second)) / edge_m;
      const double theta = std::acos(std::clamp(normals[t].dot(normals[it->second]), -1.0, 1.0));
      if (theta > 1e-9) m.min_bend_radius_m = std::min(m.min_bend_radius_m, heights_m / 3.0 / theta);
    }
  }
  return m;
}

}  // namespace cell
