#pragma once
// A sheet shape interpolated from scanned markers: where to start the equilibrium solve of a
// stage so that it lands on the branch the real sheet is on.
//
// Why: a slack sheet between clamps has several equilibria (a free corner folds up or down, a
// wrinkle sits left or right), and which one a simulation reaches depends on the mesh and on
// every step of the path. Two meshes of the same material, moved along the same path, can end
// up 10+ cm apart at a corner. Starting from the scanned shape puts the solve in the basin of
// the observed equilibrium, so that what remains between simulation and scan is the material
// and the model, not the luck of the path.
//
// Method: moving least squares with an affine basis. Each vertex takes the position of the
// affine map uv -> x fitted (Gaussian weights in material distance) to its nearest seen
// markers; vertices outside the marker grid are extrapolated by the same fit.

#include <vector>

#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

struct ObservedShapeOptions {
  int neighbours = 9;  // markers per vertex fit (at least 3 not on a line are needed)
};

// Positions (3n, m) of the mesh's vertices interpolated from the observed markers (m, world;
// NaN rows = not seen) at material points marker_uv_m. Throws std::invalid_argument when the
// counts differ or fewer than 3 markers were seen.
VecX shape_from_markers(const SheetMesh& mesh, const std::vector<Vec2>& marker_uv_m,
                        const std::vector<Vec3>& observed_m, const ObservedShapeOptions& options = {});

}  // namespace twin
