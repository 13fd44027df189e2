#include "twin/mesh/sheet_mesh.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace twin {
namespace {

double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

// Triangulates the strip between two rows of vertices (ids in increasing u, both rows spanning
// the full width, `bottom` at the lower v). Each step adds the shorter of the two possible new
// diagonals, which keeps the triangles near-equilateral and the mesh mirror-symmetric at both
// side edges; equal diagonals (aligned rows) advance the bottom row, giving the single-diagonal
// grid.
void zip_rows(const std::vector<int>& bottom, const std::vector<int>& top,
              const std::vector<Vec2>& uv, std::vector<std::array<int, 3>>& triangles) {
  std::size_t i = 0, k = 0;
  while (i + 1 < bottom.size() || k + 1 < top.size()) {
    bool advance_bottom;
    if (i + 1 >= bottom.size()) {
      advance_bottom = false;
    } else if (k + 1 >= top.size()) {
      advance_bottom = true;
    } else {
      const double bottom_diagonal = (uv[bottom[i + 1]] - uv[top[k]]).norm();
      const double top_diagonal = (uv[top[k + 1]] - uv[bottom[i]]).norm();
      advance_bottom = bottom_diagonal <= top_diagonal * (1.0 + 1e-9);
    }
    if (advance_bottom) {
      triangles.push_back({bottom[i], bottom[i + 1], top[k]});
      ++i;
    } else {
      triangles.push_back({bottom[i], top[k + 1], top[k]});
      ++k;
    }
  }
}

void require_positive(double value, const char* name) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(std::string("sheet: ") + name +
                                " must be a positive finite length in metres, got " +
                                std::to_string(value));
  }
}

}  // namespace

double SheetMesh::rest_area(int t) const {
  const auto& tri = triangles[t];
  return signed_area(rest_uv[tri[0]], rest_uv[tri[1]], rest_uv[tri[2]]);
}

double SheetMesh::total_rest_area() const {
  double area = 0.0;
  for (int t = 0; t < triangle_count(); ++t) area += rest_area(t);
  return area;
}

SheetMesh make_rectangular_sheet(double width_m, double height_m, double edge_length_m,
                                 TriangulationPattern pattern) {
  require_positive(width_m, "width_m");
  require_positive(height_m, "height_m");
  require_positive(edge_length_m, "edge_length_m");
  // Refuse absurd sizes before any search over them (a tiny edge would loop for minutes).
  // A long thin sheet is bounded by each side too: one row of more than 2M cells is already more
  // than 4M triangles, and the column search below would run over half as many candidates.
  if (width_m * height_m / (edge_length_m * edge_length_m) > 2.0e6 || width_m / edge_length_m > 2.0e6 ||
      height_m / edge_length_m > 2.0e6) {
    throw std::invalid_argument("sheet: edge_length_m " + std::to_string(edge_length_m) +
                                " gives more than 4M triangles");
  }
  const bool offset = pattern == TriangulationPattern::kOffsetRows;
  long nx = std::max(1L, std::lround(width_m / edge_length_m));
  long ny = std::max(1L, std::lround(height_m / edge_length_m));
  if (offset) {
    // Rows must be sqrt(3)/2 edge lengths apart for equilateral triangles, and a few percent of
    // distortion already makes hinge bending visibly anisotropic (see bending_calibration.h).
    // Search column counts within -20..+25 % of the nominal one for the pair (nx, ny) that keeps
    // the triangles closest to equilateral, charging a little for moving away from edge_length.
    const double nominal = width_m / edge_length_m;
    double best = 1e300;
    for (long cols = std::max(1L, std::lround(0.8 * nominal));
         cols <= std::max(1L, std::lround(1.25 * nominal)); ++cols) {
      const double dx = width_m / static_cast<double>(cols);
      const long rows = std::max(1L, std::lround(height_m / (dx * std::sqrt(3.0) / 2.0)));
      const double distortion =
          std::abs(std::log(height_m / static_cast<double>(rows) / (dx * std::sqrt(3.0) / 2.0)));
      const double cost = distortion + 0.25 * std::abs(std::log(dx / edge_length_m));
      if (cost < best) {
        best = cost;
        nx = cols;
        ny = rows;
      }
    }
  }
  if (2.0 * static_cast<double>(nx + 1) * static_cast<double>(ny) > 4.0e6) {
    throw std::invalid_argument("sheet: edge_length_m " + std::to_string(edge_length_m) +
                                " gives more than 4M triangles");
  }
  const double dx = width_m / static_cast<double>(nx);
  const double dy = height_m / static_cast<double>(ny);

  SheetMesh mesh;
  std::vector<std::vector<int>> rows(ny + 1);
  for (long j = 0; j <= ny; ++j) {
    const double v = static_cast<double>(j) * dy;
    auto add = [&](double u) {
      rows[j].push_back(static_cast<int>(mesh.rest_uv.size()));
      mesh.rest_uv.emplace_back(u, v);
    };
    if (offset && j % 2 == 1) {
      // Shifted row: half-edge offset, plus the two boundary vertices that keep the edge straight.
      add(0.0);
      for (long i = 0; i < nx; ++i) add((static_cast<double>(i) + 0.5) * dx);
      add(width_m);
    } else {
      for (long i = 0; i <= nx; ++i) add(i == nx ? width_m : static_cast<double>(i) * dx);
    }
  }
  for (long j = 0; j < ny; ++j) zip_rows(rows[j], rows[j + 1], mesh.rest_uv, mesh.triangles);
  return mesh;
}

double edge_length_for_triangle_count(double width_m, double height_m, int triangles) {
  require_positive(width_m, "width_m");
  require_positive(height_m, "height_m");
  if (triangles < 2) throw std::invalid_argument("sheet: target_triangles must be >= 2");
  // An equilateral triangle of edge a has area sqrt(3)/4 a^2.
  return std::sqrt(4.0 * width_m * height_m / (std::sqrt(3.0) * static_cast<double>(triangles)));
}

void validate_sheet_mesh(const SheetMesh& mesh) {
  const int n = mesh.vertex_count();
  if (mesh.triangle_count() == 0) throw std::invalid_argument("sheet mesh has no triangles");
  std::vector<char> used(n, 0);
  double max_extent = 0.0;
  for (const Vec2& p : mesh.rest_uv) {
    if (!p.allFinite()) throw std::invalid_argument("sheet mesh has a non-finite vertex");
    max_extent = std::max(max_extent, p.cwiseAbs().maxCoeff());
  }
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= n) {
        throw std::invalid_argument("sheet mesh triangle " + std::to_string(t) +
                                    " refers to vertex " + std::to_string(tri[k]) + " of " +
                                    std::to_string(n));
      }
      used[tri[k]] = 1;
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      throw std::invalid_argument("sheet mesh triangle " + std::to_string(t) +
                                  " repeats a vertex");
    }
    const double area = mesh.rest_area(t);
    if (!(area > 1e-14 * (max_extent * max_extent + 1e-30))) {
      throw std::invalid_argument(
          "sheet mesh triangle " + std::to_string(t) +
          (area < 0 ? " is clockwise in (u, v); triangles must be counter-clockwise"
                    : " is degenerate (zero area)"));
    }
  }
  for (std::size_t p = 0; p < mesh.quadratic_patches.size(); ++p) {
    for (int v : mesh.quadratic_patches[p]) {
      if (v < 0 || v >= n) {
        throw std::invalid_argument("sheet mesh quadratic patch " + std::to_string(p) + " refers to vertex " +
                                    std::to_string(v) + " of " + std::to_string(n));
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    if (!used[i]) {
      throw std::invalid_argument("sheet mesh vertex " + std::to_string(i) +
                                  " belongs to no triangle");
    }
  }
}

}  // namespace twin
