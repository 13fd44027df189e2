#pragma once
// Which equilibrium branch a stage is on, named by its folds, so that a refinement study compares
// levels only where they hold the same shape (a flap that settled on the other side is another
// branch, not a discretisation error). A fold is a connected region of the material sheet where
// it bends tighter than a fold radius, with one sign of curvature against the sheet's own normal
// x_u x x_v: cores tighter than the radius, grown into neighbours tighter than twice it
// (hysteresis, so that a fold near the threshold does not split in two between levels), and
// kept when larger than a least area (a jaw's boundary layer is a few millimetres wide and not
// a fold). The sheet is sampled on one material grid whatever the patch, so labels of different
// levels are comparable.

#include <string>
#include <vector>

#include "sim_hw/spline_shell/spline_patch.h"

namespace sim_hw::spline_shell {

struct Fold {
  int sign = 0;                  // +1: the sheet curves towards its normal x_u x x_v, -1: away
  Vec2 centre_m = Vec2::Zero();  // material centroid
  double area_m2 = 0;
  double peak_curvature_1_m = 0;  // the largest principal curvature's magnitude in it
  std::vector<Vec2> cells_m;       // the material grid's cells it covers (their centres)
};

struct BranchLabel {
  std::vector<Fold> folds;  // largest first
  // Bends: regions tighter than twice the fold radius with no core tighter than it, of at least
  // the least area. A coarser level draws a fold it resolves too coarsely as a bend of the same
  // sign in the same place: a fold that sharpens under refinement, not another branch.
  std::vector<Fold> bends;
  // "2 folds: +(120, 310) mm 31 cm^2, -(400, 95) mm 12 cm^2" or "no fold".
  std::string text() const;
};

struct FoldOptions {
  double fold_radius_m = 0.03;  // folds have radii of 2-5 cm (the composite's gravity length is about 4)
  double sample_m = 0.005;      // material grid
  double least_area_m2 = 4e-4;  // (2 cm)^2
};

BranchLabel branch_label(const SplinePatch& patch, const VecX& x, const FoldOptions& options = {});

// Same branch: every fold of at least significant_area_m2 in either label lies, for at least half
// its cells, within tolerance_m of the other's folds or bends of the same sign. A fold may split,
// merge, shrink or sharpen out of a bend between levels, and smaller folds come and go (a region
// near the fold radius grows past the least area on one level and not on the next); a flap that
// turned over, or a fold that is gone or moved by more than its width, is another branch. `why`
// says which fold differs.
bool same_branch(const BranchLabel& a, const BranchLabel& b, double tolerance_m = 0.02, double significant_area_m2 = 1e-3,
                 std::string* why = nullptr);

}  // namespace sim_hw::spline_shell
