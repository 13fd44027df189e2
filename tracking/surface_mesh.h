#pragma once
// The sheet's surface as the tracker sees it: a triangle mesh as plain data. The cell fills it
// from the twin's predicted mesh (same vertex order), so tracking never needs to know the twin.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tracking/types.h"

namespace tracking {

struct SurfaceMesh {
  std::vector<Vec3> vertices_m;            // cell frame (m)
  std::vector<Eigen::Vector3i> triangles;  // vertex indices, counter-clockwise seen from +n
  std::vector<Eigen::Vector2d> rest_uv_m;  // optional material coordinates (m); may be empty
};

// Empty when the mesh is usable; otherwise what is wrong (no vertices, index out of range,
// non-finite vertex, degenerate triangle, rest coordinates of the wrong count).
std::string validate_mesh(const SurfaceMesh& mesh);

// Each undirected edge once, (i, j) with i < j, sorted.
std::vector<std::pair<int, int>> unique_edges(const std::vector<Eigen::Vector3i>& triangles);

// Area (m^2) owned by each vertex: a third of the area of each triangle around it.
std::vector<double> vertex_areas(const std::vector<Vec3>& vertices_m,
                                 const std::vector<Eigen::Vector3i>& triangles);

// Unit vertex normals, area-weighted average of the adjacent triangles' normals (zero for a
// vertex without triangles).
std::vector<Vec3> vertex_normals(const std::vector<Vec3>& vertices_m,
                                 const std::vector<Eigen::Vector3i>& triangles);

// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// For each vertex, the triangles around it (indices into `triangles`).
std::vector<std::vector<int>> vertex_triangles(int vertex_count,
                                               const std::vector<Eigen::Vector3i>& triangles);

// A flat regular grid in the plane z = 0, centred on the origin: cols x rows vertices spanning
// width_m (x) by height_m (y), two triangles per cell, rest_uv_m = (x, y). Used by tests and the
// benchmark to make meshes the size of the twin's.
SurfaceMesh make_grid_mesh(double width_m, double height_m, int cols, int rows);

}  // namespace tracking
