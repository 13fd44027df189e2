// Mesh checks and per-vertex geometry shared by registration and coverage.
#include "tracking/surface_mesh.h"

#include <algorithm>

#include <fmt/format.h>

namespace tracking {

std::string validate_mesh(const SurfaceMesh& mesh) {
  const int n = static_cast<int>(mesh.vertices_m.size());
  if (n == 0) return "mesh has no vertices";
  if (mesh.triangles.empty()) return "mesh has no triangles";
  for (int i = 0; i < n; ++i) {
    if (!mesh.vertices_m[i].allFinite()) return fmt::format("vertex {} is not finite", i);
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= n) {
        return fmt::format("triangle {} has vertex index {} outside [0, {})", t, tri[k], n);
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      return fmt::format("triangle {} repeats a vertex", t);
    }
  }
  if (!mesh.rest_uv_m.empty() && static_cast<int>(mesh.rest_uv_m.size()) != n) {
    return fmt::format("mesh has {} rest coordinates for {} vertices", mesh.rest_uv_m.size(), n);
  }
  return {};
}

std::vector<std::pair<int, int>> unique_edges(const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(triangles.size() * 3);
  for (const Eigen::Vector3i& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

std::vector<double> vertex_areas(const std::vector<Vec3>& vertices_m,
                                 const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<double> area(vertices_m.size(), 0.0);
  for (const Eigen::Vector3i& t : triangles) {
    const double a =
        0.5 *
        (vertices_m[t[1]] - vertices_m[t[0]]).cross(vertices_m[t[2]] - vertices_m[t[0]]).norm();
    for (int k = 0; k < 3; ++k) area[t[k]] += a / 3.0;
  }
  return area;
}

std::vector<Vec3> vertex_normals(const std::vector<Vec3>& vertices_m,
                                 const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<Vec3> normal(vertices_m.size(), Vec3::Zero());
  for (const Eigen::Vector3i& t : triangles) {
    // The unnormalised cross product is twice the area times the unit normal: area weighting.
    const Vec3 n = (vertices_m[t[1]] - vertices_m[t[0]]).cross(vertices_m[t[2]] - vertices_m[t[0]]);
    for (int k = 0; k < 3; ++k) normal[t[k]] += n;
  }
  for (Vec3& n : normal) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
  return normal;
}

SurfaceMesh make_grid_mesh(double width_m, double height_m, int cols, int rows) {
  SurfaceMesh mesh;
  cols = std::max(cols, 2);
  rows = std::max(rows, 2);
  mesh.vertices_m.reserve(static_cast<std::size_t>(cols) * rows);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double x = -0.5 * width_m + width_m * c / (cols - 1);
      const double y = -0.5 * height_m + height_m * r / (rows - 1);
      mesh.vertices_m.emplace_back(x, y, 0.0);
      mesh.rest_uv_m.emplace_back(x, y);
    }
  }
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < cols; ++c) {
      const int v00 = r * cols + c, v10 = v00 + 1, v01 = v00 + cols, v11 = v01 + 1;
      mesh.triangles.emplace_back(v00, v10, v11);
      mesh.triangles.emplace_back(v00, v11, v01);
    }
  }
  return mesh;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the vertices, then of the edges, else the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

std::vector<std::vector<int>> vertex_triangles(int vertex_count,
                                               const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<std::vector<int>> around(vertex_count);
  for (int f = 0; f < static_cast<int>(triangles.size()); ++f) {
    for (int k = 0; k < 3; ++k) around[triangles[f][k]].push_back(f);
  }
  return around;
}

}  // namespace tracking
