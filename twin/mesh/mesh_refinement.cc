#include "twin/mesh/mesh_refinement.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace twin {
namespace {

using Edge = std::pair<int, int>;  // (smaller, larger) vertex index

Edge edge_key(int a, int b) { return a < b ? Edge{a, b} : Edge{b, a}; }

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Distance (m) from p to the closed triangle abc (counter-clockwise): 0 inside.
double point_triangle_distance(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  if (cross(b - a, p - a) >= 0.0 && cross(c - b, p - b) >= 0.0 && cross(a - c, p - c) >= 0.0) {
    return 0.0;
  }
  return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                   point_segment_distance(p, c, a)});
}

// `mesh` with the triangles marked red split into four (and the closure described in the header).
// A red triangle t's four are appended in the order (a, ab, ca), (ab, b, bc), (ca, bc, c),
// (ab, bc, ca), so that with every triangle red, triangle 4t + 3 holds t's three midpoints.
SheetMesh refine_marked(const SheetMesh& mesh, std::vector<char> red) {
  const int triangle_count = mesh.triangle_count();
  // Closure: a triangle with two or more split edges is split red as well, which may split
  // further edges; every pass only adds red triangles, so it ends.
  std::map<Edge, int> midpoint;  // split edge -> new vertex (assigned below)
  auto split_edges_of = [&](int t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) midpoint.emplace(edge_key(tri[k], tri[(k + 1) % 3]), -1);
  };
  for (int t = 0; t < triangle_count; ++t) {
    if (red[t]) split_edges_of(t);
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (int t = 0; t < triangle_count; ++t) {
      if (red[t]) continue;
      const auto& tri = mesh.triangles[t];
      int split = 0;
      for (int k = 0; k < 3; ++k) split += midpoint.count(edge_key(tri[k], tri[(k + 1) % 3])) > 0;
      if (split >= 2) {
        red[t] = 1;
        split_edges_of(t);
        changed = true;
      }
    }
  }

  SheetMesh out;
  out.rest_uv = mesh.rest_uv;
  for (auto& [edge, vertex] : midpoint) {
    vertex = static_cast<int>(out.rest_uv.size());
    out.rest_uv.push_back(0.5 * (mesh.rest_uv[edge.first] + mesh.rest_uv[edge.second]));
  }
  auto mid = [&](int a, int b) {
    const auto it = midpoint.find(edge_key(a, b));
    return it == midpoint.end() ? -1 : it->second;
  };
  for (int t = 0; t < triangle_count; ++t) {
    const auto& tri = mesh.triangles[t];
    if (red[t]) {
      const int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
      out.triangles.push_back({tri[0], ab, ca});
      out.triangles.push_back({ab, tri[1], bc});
      out.triangles.push_back({ca, bc, tri[2]});
      out.triangles.push_back({ab, bc, ca});
      continue;
    }
    bool bisected = false;
    for (int k = 0; k < 3 && !bisected; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      const int m = mid(a, b);
      if (m < 0) continue;
      out.triangles.push_back({a, m, c});  // orientation kept: m lies on a-b
      out.triangles.push_back({m, b, c});
      bisected = true;
    }
    if (!bisected) out.triangles.push_back(tri);
  }
  return out;
}

SheetMesh refine_once(const SheetMesh& mesh, const std::vector<Vec2>& points, double radius_m) {
  std::vector<char> red(mesh.triangle_count(), 0);
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (const Vec2& p : points) {
      if (point_triangle_distance(p, mesh.rest_uv[tri[0]], mesh.rest_uv[tri[1]], mesh.rest_uv[tri[2]]) <=
          radius_m) {
        red[t] = 1;
        break;
      }
    }
  }
  return refine_marked(mesh, std::move(red));
}

}  // namespace

SheetMesh refine_uniformly(const SheetMesh& mesh) {
  validate_sheet_mesh(mesh);
  SheetMesh out = refine_marked(mesh, std::vector<char>(mesh.triangle_count(), 1));
  out.quadratic_patches.reserve(mesh.triangles.size());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& corners = mesh.triangles[t];
    const auto& midpoints = out.triangles[4 * static_cast<std::size_t>(t) + 3];
    out.quadratic_patches.push_back({corners[0], corners[1], corners[2], midpoints[0], midpoints[1], midpoints[2]});
  }
  validate_sheet_mesh(out);
  return out;
}

SheetMesh refine_near_points(const SheetMesh& mesh, const std::vector<Vec2>& points_uv_m,
                             const std::vector<double>& radii_m) {
  SheetMesh out = mesh;
  for (std::size_t i = 0; i < radii_m.size(); ++i) {
    const double r = radii_m[i];
    if (!(std::isfinite(r) && r >= 0.0)) {
      throw std::invalid_argument("mesh refinement level " + std::to_string(i + 1) +
                                  ": radius_m must be a finite length >= 0 (m), got " + std::to_string(r));
    }
    if (points_uv_m.empty()) break;
    out = refine_once(out, points_uv_m, r);
  }
  validate_sheet_mesh(out);
  return out;
}

}  // namespace twin
