#include "twin/mesh/material_point.h"

#include <stdexcept>

#include <fmt/format.h>

namespace twin {

Vec3 rest_barycentric(const SheetMesh& mesh, int t, const Vec2& uv) {
  const auto& tri = mesh.triangles[t];
  Mat2 edges;
  edges.col(0) = mesh.rest_uv[tri[1]] - mesh.rest_uv[tri[0]];
  edges.col(1) = mesh.rest_uv[tri[2]] - mesh.rest_uv[tri[0]];
  const Vec2 bc = edges.inverse() * (uv - mesh.rest_uv[tri[0]]);
  return Vec3(1.0 - bc.sum(), bc.x(), bc.y());
}

std::optional<MaterialPointLocation> locate_material_point(const SheetMesh& mesh, const Vec2& uv) {
  if (!uv.allFinite()) return std::nullopt;
  // A linear scan: points are located once per mesh (markers, clamps), and a few hundred
  // points times a few thousand triangles is milliseconds.
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const Vec3 w = rest_barycentric(mesh, t, uv);
    // The tolerance admits points on an edge or a corner of the sheet (a marker on the border).
    if (w.minCoeff() >= -1e-9) {
      MaterialPointLocation location;
      location.triangle = t;
      location.vertices = mesh.triangles[t];
      location.weights = w;
      return location;
    }
  }
  return std::nullopt;
}

MaterialPointMap::MaterialPointMap(const SheetMesh& mesh, const std::vector<Vec2>& points_uv_m) {
  locations_.reserve(points_uv_m.size());
  for (std::size_t i = 0; i < points_uv_m.size(); ++i) {
    const auto location = locate_material_point(mesh, points_uv_m[i]);
    if (!location) {
      throw std::invalid_argument(fmt::format("material point {} at ({:.4g}, {:.4g}) m is not on the sheet",
                                              i, points_uv_m[i].x(), points_uv_m[i].y()));
    }
    locations_.push_back(*location);
  }
}

std::vector<Vec3> MaterialPointMap::positions(const VecX& x) const {
  std::vector<Vec3> p;
  p.reserve(locations_.size());
  for (const auto& location : locations_) p.push_back(location.position(x));
  return p;
}

void MaterialPointMap::add_gradient(const std::vector<Vec3>& d_points, VecX& d_x) const {
  for (std::size_t i = 0; i < locations_.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      d_x.segment<3>(3 * locations_[i].vertices[k]) += locations_[i].weights(k) * d_points[i];
    }
  }
}

}  // namespace twin
