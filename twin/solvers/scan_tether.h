#pragma once
// An equilibrium in the basin of a scanned shape, found by letting go of the scan gradually.
//
// A slack hanging sheet has many equilibria (corners fold up or down, wrinkles sit left or
// right). To find the one the real sheet was in, the sheet starts at its scanned shape
// (observed_shape.h) with every seen marker tied to where it was seen by a spring, and is
// solved to equilibrium while the springs are weakened step by step to nothing: a homotopy
// from "shaped by the scan" to "shaped by its own mechanics" that never leaves the basin the
// scan put it in. The last solve has no springs: the result is an equilibrium of the model.

#include <vector>

#include "twin/model/clamp.h"
#include "twin/model/energy_term.h"
#include "twin/mesh/material_point.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/solve_report.h"

namespace twin {

// E = sum over seen markers of k/2 |p_m(x) - o_m|^2 (J), p_m the marker's material point in x,
// o_m its observed position (m), k (N/m) the spring stiffness.
class MarkerTetherTerm final : public ElementTerm<3> {
 public:
  MarkerTetherTerm(const MaterialPointMap& markers, const std::vector<Vec3>& observed_m, int vertex_count);
  std::string_view name() const override { return "marker tether"; }
  void set_stiffness(double k_N_m) { k_N_m_ = k_N_m; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override;

 private:
  std::vector<Vec3> weights_, targets_m_;
  double k_N_m_ = 0.0;
};

// How the springs are let go: their stiffness per marker, in units of the marker's share of the
// sheet's weight per metre of stretch, from `first` down to `last` by factors of `ratio`, then
// none.
struct TetherRelease {
  double first = 1e4, last = 0.1, ratio = 10.0;
};
// Pinned, then let go: the markers held to the scan within its noise (the sheet between them
// takes its own shape there), then weakened by decades until no longer felt. For a start that is
// already an equilibrium near the scan (the path's): it keeps the shape's wrinkles where the scan
// has them. Decades rather than the half-decades it began with: 11 solves instead of 20, and on
// the benchmark pair (2508-triangle twin, jaw-resolved lab) the whole identification took 17.0-18.6 s
// instead of 21.6-22.2 s with the same fit (test 1.6 mm); at the lab's true material the kept
// equilibria of three lab trials were 1.81, 1.79 and 1.26 mm from the scans (mean) against
// 2.83, 1.76 and 1.26 mm. From a start interpolated between markers it did better than the
// default on the lab's own mesh but 11 mm worse (mean) on a released stage of a twin coarser
// than the lab's sheet, so the evaluator keeps the default for that start (trial_evaluator.cc).
inline constexpr TetherRelease kPinnedTetherRelease{1e6, 1e-3, 10.0};

// x: on entry any start (the scanned shape, say); on success the equilibrium reached by the
// homotopy, a stable one (its exact Hessian positive definite). On failure x is unchanged; a
// homotopy that ends on a saddle, held up by the last weak springs, is a failure (kIndefinite):
// seen on a blind set (7003), where the kept saddle then broke every later sensitivity.
SolveReport equilibrium_from_scan(const ShellModel& model, const ClampSet& clamps,
                                  const std::vector<ClampPose>& poses, const MaterialPointMap& markers,
                                  const std::vector<Vec3>& observed_m, VecX& x,
                                  const TetherRelease& release = {});

}  // namespace twin
