#pragma once
// Conversions and comparisons between the twin's sheet, the tracker's mesh and the fake world's
// true sheet (SIM_SHEET_TRUTH), for the tracker's prediction and the experiment's table.
#include <vector>

#include "tracking/surface_mesh.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace cell {

// The twin's mesh at positions x (3n, m) as the tracker's mesh (with its material coordinates).
tracking::SurfaceMesh tracking_mesh(const twin::SheetMesh& mesh, const twin::VecX& x);

struct SurfaceGap {
  int points = 0;
  double mean_m = 0, max_m = 0;
};
// Distance from each point to the nearest point of the triangle mesh (mesh triangles over
// vertices_m), mean and max. Brute force with a bounding-sphere cut: a few ms for a few thousand
// points on a 1500-triangle mesh. The world's true sheet has its own mesh, so it is compared
// point (truth vertex) to surface (twin or tracked), which carries no mesh-spacing bias.
SurfaceGap points_to_surface(const std::vector<twin::Vec3>& points,
                             const std::vector<twin::Vec3>& vertices_m,
                             const std::vector<Eigen::Vector3i>& triangles);

}  // namespace cell
