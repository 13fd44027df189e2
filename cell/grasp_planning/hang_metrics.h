#pragma once
// How a held ply hangs, measured on the twin's equilibrium (positions x, 3n, m, z up): the
// quantities the grasp goal limits (grasp_goal.h).
#include <limits>

#include "cell/grasp_planning/grasp_goal.h"
#include "twin/mesh/sheet_mesh.h"

namespace cell {

struct HangMetrics {
  double lowest_z_m = 0.0;  // lowest vertex of the ply
  double sag_m = 0.0;       // hold height minus the lowest vertex
  // Lowest ply point above the tool's top rectangle minus the top height (m); the lowest point
  // of the whole ply when the tool has no size; +inf when no ply point is above the rectangle.
  double clearance_m = std::numeric_limits<double>::infinity();
  // Smallest bend radius over all hinges (m): a hinge whose two triangles turn by angle theta
  // (between their normals) over the distance d between their centroids across the shared edge
  // (d = (h_A + h_B) / 3 with h the triangles' rest heights over that edge) has radius d / theta.
  // A hinge sees the curvature across it only: on offset-row meshes, whose edges are 0, 60 and
  // 120 degrees from u, a cylinder bent along u reads up to 1 / cos(30 deg) = 1.15 times its
  // radius (tested).
  double min_bend_radius_m = std::numeric_limits<double>::infinity();
  // Share of the rest area whose normal (the side facing up when the ply was laid out flat)
  // points more than 30 degrees below horizontal (n_z < -0.5): turned over.
  double overturned_fraction = 0.0;
};

HangMetrics measure_hang(const twin::SheetMesh& mesh, const twin::VecX& x, double hold_z_m,
                         const ToolSpec& tool);

}  // namespace cell
