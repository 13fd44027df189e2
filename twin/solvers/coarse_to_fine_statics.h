#pragma once
// Static equilibrium from far away (a flat sheet, a fresh grasp) through coarser meshes of the
// same sheet: the equilibrium is found on the coarsest mesh, carried to the next finer mesh by
// interpolation at each vertex's material point, solved there from that start, and so on up to
// the caller's mesh.
//
// Why: from flat, Newton on a fine sheet spends most of its iterations finding the sag and the
// wrinkles, each iteration a fine factorisation. On a mesh with 4x fewer triangles an
// iteration costs about 8x less (nested-dissection fill), and the fine solve then only corrects
// what the coarse mesh could not show (the hinge angles of the finer triangulation, wrinkles
// shorter than a coarse edge). It changes where Newton starts, not what it converges to: the
// result is an equilibrium of the caller's model to the caller's tolerance. A sheet with several
// equilibria (wrinkled, folded) may end on another of them than a solve from the caller's start
// would; issue 37's accuracy checks compare both where they reach the same one.
//
// When the solve from the interpolated start fails, the plain solve (StaticSolver::solve from
// the caller's start, settling included) runs instead and the report counts it as a fallback.

#include <memory>
#include <vector>

#include "twin/mesh/material_point.h"
#include "twin/solvers/static_solver.h"

namespace twin {

struct CoarseToFineReport {
  SolveReport total;                  // every level's solves, the outcome the fine mesh's
  std::vector<SolveReport> levels;    // coarsest first, the fine mesh last
  std::vector<int> level_triangles;   // likewise
  bool fell_back = false;             // with levels: the fine solve ran from the caller's start
};

class CoarseToFineStatics {
 public:
  // `coarse_meshes`: meshes of the same sheet (same material coordinates), any order; each must
  // cover every vertex of the next finer one and every clamp's point, else std::invalid_argument
  // naming the mesh. Meshes with at least 2/3 of the finer level's triangles are skipped (no
  // gain). `fine` and `fine_clamps` must outlive this object; the coarse models copy the fine
  // model's material, load age, clamp effects and marker masses at every solve.
  CoarseToFineStatics(const ShellModel& fine, const ClampSet& fine_clamps,
                      std::vector<SheetMesh> coarse_meshes);
  ~CoarseToFineStatics();

  // The levels in use, coarsest first (the fine mesh not included).
  int level_count() const { return static_cast<int>(levels_.size()); }

  // As StaticSolver::solve(fine_clamps, poses, x, options): on success x (3n of the fine mesh)
  // is the fine model's equilibrium; otherwise x is unchanged.
  CoarseToFineReport solve(const std::vector<ClampPose>& poses, VecX& x,
                           const NewtonOptions& options = default_static_options());

 private:
  struct Level;
  void sync_level(Level& level) const;

  const ShellModel& fine_;
  const ClampSet& fine_clamps_;
  StaticSolver fine_statics_;
  std::vector<std::unique_ptr<Level>> levels_;  // coarsest first
};

// Positions (3n of `to`'s vertices) of a sheet at x on the mesh the map was built on, for a map
// built at every vertex of `to` (MaterialPointMap(from_mesh, to.rest_uv)).
VecX interpolate_positions(const MaterialPointMap& to_vertices, const VecX& x);

}  // namespace twin
