#pragma once
// Where a material point (u, v) sits in the rest mesh: its host triangle and barycentric
// weights. A point of the sheet (a marker, a clamp's centre) then moves with the deformed mesh
// as the same weighted sum of its triangle's vertex positions.

#include <array>
#include <optional>
#include <vector>

#include "twin/mesh/sheet_mesh.h"

namespace twin {

struct MaterialPointLocation {
  int triangle = -1;
  std::array<int, 3> vertices{};  // the host triangle's vertex ids
  Vec3 weights = Vec3::Zero();    // barycentric, summing to 1
  // World position of the point in the sheet at positions x (3n, m).
  Vec3 position(const VecX& x) const {
    return weights(0) * x.segment<3>(3 * vertices[0]) + weights(1) * x.segment<3>(3 * vertices[1]) +
           weights(2) * x.segment<3>(3 * vertices[2]);
  }
};

// Barycentric coordinates of uv in rest triangle t.
Vec3 rest_barycentric(const SheetMesh& mesh, int t, const Vec2& uv);

// The triangle holding uv (points on an edge included), or nullopt when uv is off the sheet.
std::optional<MaterialPointLocation> locate_material_point(const SheetMesh& mesh, const Vec2& uv);

// Material points that move with a mesh (markers): positions for a deformed state and the
// transpose map for gradients. Throws std::invalid_argument naming the first point off the sheet.
class MaterialPointMap {
 public:
  MaterialPointMap(const SheetMesh& mesh, const std::vector<Vec2>& points_uv_m);
  int size() const { return static_cast<int>(locations_.size()); }
  const MaterialPointLocation& location(int i) const { return locations_[i]; }
  std::vector<Vec3> positions(const VecX& x) const;
  // Adds dJ/dx (3n) for dJ/dp_i given per point (the transpose of positions()).
  void add_gradient(const std::vector<Vec3>& d_points, VecX& d_x) const;

 private:
  std::vector<MaterialPointLocation> locations_;
};

}  // namespace twin
