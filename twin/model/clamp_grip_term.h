#pragma once
// Clamp grip (model_effects.h "clamp_grip"): the jaws hold a wider patch than the clamp's grip
// radius says. The trial file gives each clamp a grip radius r; real jaws often press on more
// of the ply (a wider bar, a rubber pad that spreads). With width w and strength s the material
// up to w beyond r is held too, s times as firmly as a vertex of the clamp's own patch would be
// by kGripStiffness_N_m3.
//
// Each vertex i outside every clamp's held patch and within kMaxClampGripWidth_m (model_effects.h)
// plus one vertex size of a clamp's radius (excess e_i = distance from the clamp's material
// point - r, in the rest state) is tied to where the clamp's rigid patch would put it: the
// affine extension of the clamp's host triangle (held rigidly in its rest shape, so the
// extension is exactly p + R (u_i - u_c)).
//   E_i = 1/2 k_i |x_i - sum_j lambda_ij x_hj|^2                          (J)
//   k_i = s * kGripStiffness_N_m3 * A_i * clamp(1 + (w - e_i) / h_i, 0, 1)  (N/m)
// with A_i the vertex's lumped rest area (m^2) and h_i = sqrt(A_i) its size (m). The last factor
// is the share of the vertex's cell the jaws cover: 1 once the width passes the vertex, 0 from
// one vertex size beyond it, so the effect changes continuously with w on any mesh. Strength 0
// is the effect's absence, and the energy is linear in s: a score test at s = 0 (with w at a
// default) sees it, where an infinitesimal widening of a patch on a coarse mesh would move no
// vertex. The energy is quadratic in x: the gradient and Hessian are exact.
//
// The springs of one clamp all share its host triangle, so they cannot be coloured into
// parallel batches (ElementTerm would make one OpenMP region per spring): they are summed in one
// serial pass, which costs nothing at strength 0.
//
// A released clamp grips nothing: which clamps are engaged is set by whoever solves or
// differentiates with given poses (set_engaged). The springs are built once from the clamps
// (set_clamps) and never change afterwards, so solvers' sparsity patterns stay valid.

#include <vector>

#include "twin/model/clamp.h"
#include "twin/model/energy_term.h"
#include "twin/model/model_effects.h"

namespace twin {

class ClampGripTerm final : public EnergyTerm {
 public:
  // Stiffness per unit area (N/m^3) at strength 1: on a 300-triangle composite sheet a vertex
  // (about 7e-3 m^2) is held at ~7e4 N/m, so the sheet's weight (3.4 N) moves it by < 0.1 mm.
  static constexpr double kGripStiffness_N_m3 = 1e7;

  explicit ClampGripTerm(int vertex_count);
  std::string_view name() const override { return "clamp_grip"; }
  int arity() const override { return 4; }
  // Per spring: the vertex, then its clamp's host triangle.
  const std::vector<int>& element_vertices() const override { return vertices_; }
  double evaluate(const VecX& x, VecX* grad, const HessianTarget* hess, HessianMode mode) const override;

  // Builds the springs of `clamps` on `mesh` (the model's). Replaces earlier ones; all clamps
  // start engaged. Call before solvers are built on the model (they keep its sparsity).
  void set_clamps(const SheetMesh& mesh, const ClampSet& clamps);
  int clamp_count() const { return clamp_count_; }
  int spring_count() const { return static_cast<int>(springs_.size()); }

  void set_grip(double strength, double width_m) {
    strength_ = strength;
    width_m_ = width_m;
  }

  // Engaged clamps grip (poses.size() must be clamp_count(); no clamps set: nothing to do).
  // Const because it is hold state, like the poses a solver is given; throws
  // std::invalid_argument for a wrong count.
  void set_engaged(const std::vector<ClampPose>& poses) const;

  // k_i (N/m) of spring `spring` at the current grip and engagement.
  double spring_stiffness_N_m(int spring) const;

 private:
  struct Spring {
    int clamp = 0;
    Vec3 affine = Vec3::Zero();  // lambda of the host triangle's vertices
    double excess_m = 0.0;
    double area_m2 = 0.0;
    double size_m = 0.0;  // sqrt(area)
  };
  int vertex_count_ = 0;
  int clamp_count_ = 0;
  std::vector<Spring> springs_;
  std::vector<int> vertices_;
  double strength_ = 0.0;
  double width_m_ = 0.0;
  mutable std::vector<char> engaged_;
};

}  // namespace twin
