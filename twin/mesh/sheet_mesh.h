#pragma once
// The sheet's rest state: a flat triangle mesh in 2D material coordinates.
//   u = weft direction (m), v = warp direction (m).
// Triangles are counter-clockwise in (u, v). The world placement of the sheet is not part of
// the mesh (see SheetPlacement in scenario.h); the mesh only defines the material.

#include <array>
#include <vector>

#include "twin/base/types.h"

namespace twin {

struct SheetMesh {
  std::vector<Vec2> rest_uv;                   // #V material coordinates (m)
  std::vector<std::array<int, 3>> triangles;  // #F vertex indices, CCW in (u, v)
  // When the mesh is a coarser one refined uniformly (refine_uniformly, mesh_refinement.h): per
  // coarse triangle its corners a, b, c and the midpoints of ab, bc, ca (the six nodes of the
  // quadratic membrane, quadratic_membrane.h). Empty otherwise; any other change of the mesh
  // drops them.
  std::vector<std::array<int, 6>> quadratic_patches;

  int vertex_count() const { return static_cast<int>(rest_uv.size()); }
  int triangle_count() const { return static_cast<int>(triangles.size()); }
  double rest_area(int triangle) const;  // m^2
  double total_rest_area() const;        // m^2
};

enum class TriangulationPattern {
  // Rows of near-equilateral triangles, every other row shifted by half an edge. Hinge bending
  // on this pattern is close to isotropic (see bending_calibration.h). The default.
  kOffsetRows,
  // Regular grid of squares split along one diagonal. Strongly direction-dependent in bending;
  // kept only to demonstrate and test that dependence.
  kRightTriangles,
};

// Rectangle [0, width] x [0, height] in material coordinates, edges of about edge_length.
// Throws std::invalid_argument on non-positive or non-finite sizes or a mesh over 4M triangles.
SheetMesh make_rectangular_sheet(double width_m, double height_m, double edge_length_m,
                                 TriangulationPattern pattern = TriangulationPattern::kOffsetRows);

// Edge length that gives about `triangles` near-equilateral triangles on a width x height sheet.
double edge_length_for_triangle_count(double width_m, double height_m, int triangles);

// Checks indices, orientation and degeneracy; throws std::invalid_argument naming the triangle.
void validate_sheet_mesh(const SheetMesh& mesh);

}  // namespace twin
