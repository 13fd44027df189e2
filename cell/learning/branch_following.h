#pragma once
// Branch following (issue 35): a slack hanging sheet has many equilibria (a corner folded up or
// down), and the twin's own path can pick another than the real sheet's. When the cameras show
// the settled sheet, the twin's equilibrium in the basin of that shape is found
// (twin/solvers/scan_tether.h: tied to the observation by springs let go step by step) on a copy
// of the twin's model, off the twin's own thread; the cell re-seeds the twin with it when it is
// nearer the observation than the twin's state by a clear margin and the grasps have not moved
// meanwhile.
#include <string>
#include <vector>

#include "twin/mesh/sheet_mesh.h"
#include "twin/model/clamp.h"
#include "twin/model/material.h"

namespace cell::learning {

struct BranchCandidate {
  std::string problem;  // why no equilibrium was found ("" when one was)
  twin::VecX x;         // the equilibrium (3n, m); empty on a problem
  double before_m = 0.0, after_m = 0.0;  // mean distance of `current` / x to the seen vertices
  // Nearer the observation than the current state by at least min_gain of its distance.
  bool better(double min_gain) const { return problem.empty() && after_m < (1.0 - min_gain) * before_m; }
};

// `observed_m`: per vertex of `mesh`, the settled sheet as seen (NaN: not seen). `current`: the
// twin's state (3n), the start where a vertex was not seen. Clamps and poses as the twin holds
// the sheet. Never throws for numerical trouble (problem says why); throws
// std::invalid_argument for sizes that do not match the mesh.
BranchCandidate equilibrium_near_observation(const twin::SheetMesh& mesh, const twin::Material& material,
                                             const std::vector<twin::ClampSpec>& clamps,
                                             const std::vector<twin::ClampPose>& poses, const twin::VecX& current,
                                             const std::vector<twin::Vec3>& observed_m);

}  // namespace cell::learning
