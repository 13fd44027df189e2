#pragma once
// Local refinement of a sheet mesh around material points (the clamps).
//
// A hanging sheet is sharply curved where a clamp holds it, and a clamp's jaws (a grip radius of
// 1-2 cm) are smaller than a coarse twin's triangles, which then hold a whole 4 cm triangle
// rigid. Both errors shrink only with smaller elements near the clamps; elsewhere the sheet is
// gently curved and a coarse mesh does. Refining there alone costs far fewer triangles than a
// uniformly finer mesh.
//
// Red-green refinement: every triangle that comes within `radius_m` of a point is split into
// four by its edge midpoints (red, same shape); a neighbour with two or three split edges is
// split red too, until none is left; a neighbour with one split edge is bisected (green) so that
// no vertex hangs. Levels repeat it with their own radius on the result: use radii that shrink
// by at least two coarse edge lengths per level so that no green triangle is split again.

#include <vector>

#include "twin/mesh/sheet_mesh.h"

namespace twin {

// Every triangle split into four by its edge midpoints; the result's quadratic_patches list each
// original triangle with its midpoints (the quadratic membrane's elements). Vertices of `mesh`
// keep their indices. Throws std::invalid_argument for an invalid mesh.
SheetMesh refine_uniformly(const SheetMesh& mesh);

// The mesh with one level per radius (m, material coordinates), applied in order. Vertices of
// `mesh` keep their indices; new vertices follow. Throws std::invalid_argument on a negative or
// non-finite radius.
SheetMesh refine_near_points(const SheetMesh& mesh, const std::vector<Vec2>& points_uv_m,
                             const std::vector<double>& radii_m);

}  // namespace twin
