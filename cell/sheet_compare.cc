#include "cell/sheet_compare.h"

#include <algorithm>
#include <limits>

namespace cell {

tracking::SurfaceMesh tracking_mesh(const twin::SheetMesh& mesh, const twin::VecX& x) {
  tracking::SurfaceMesh out;
  out.vertices_m.reserve(mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    out.vertices_m.push_back(twin::vertex(x, i));
    out.rest_uv_m.push_back(mesh.rest_uv[i]);
  }
  for (const auto& t : mesh.triangles) out.triangles.emplace_back(t[0], t[1], t[2]);
  return out;
}

SurfaceGap points_to_surface(const std::vector<twin::Vec3>& points,
                             const std::vector<twin::Vec3>& v,
                             const std::vector<Eigen::Vector3i>& triangles) {
  SurfaceGap gap;
  if (triangles.empty()) return gap;
  std::vector<twin::Vec3> centre(triangles.size());
  std::vector<double> radius(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    centre[f] = (v[t[0]] + v[t[1]] + v[t[2]]) / 3.0;
    radius[f] = 0;
    for (int k = 0; k < 3; ++k) radius[f] = std::max(radius[f], (v[t[k]] - centre[f]).norm());
  }
  double sum = 0;
  std::size_t hint = 0;  // neighbouring points usually share a nearest triangle: start there
  for (const twin::Vec3& p : points) {
    if (!p.allFinite()) continue;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < triangles.size(); ++k) {
      const std::size_t f = (hint + k) % triangles.size();
      if ((p - centre[f]).norm() - radius[f] >= best) continue;
      const auto& t = triangles[f];
      const double d = (p - tracking::closest_point_on_triangle(p, v[t[0]], v[t[1]], v[t[2]])).norm();
      if (d < best) {
        best = d;
        hint = f;
      }
    }
    sum += best;
    gap.max_m = std::max(gap.max_m, best);
    ++gap.points;
  }
  if (gap.points > 0) gap.mean_m = sum / gap.points;
  return gap;
}

}  // namespace cell
