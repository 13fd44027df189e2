#pragma once
// Static equilibrium of the sheet under gravity with clamps held at given poses: the minimum
// of membrane + bending + gravity energy over the free vertices, by Newton (newton_solver.h).
// Hanging sheets have several equilibria; which one is found depends on the start, so callers
// that follow a real motion should use quasi_static.h.

#include "twin/model/clamp.h"
#include "twin/model/inertia_term.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/shell_model.h"

namespace twin {

NewtonOptions default_static_options();

// ||weight on the free vertices|| (N): the unit of solver residuals, so that a tolerance means
// the same on every mesh.
double free_weight_N(const ShellModel& model, const DofMap& dofs);

class StaticSolver {
 public:
  explicit StaticSolver(const ShellModel& model);

  // x (3n): the start. Clamped vertices are set to their held positions before solving. On
  // success x is the equilibrium; otherwise x is unchanged (clamped vertices included) and the
  // report says why. When Newton from x fails (far from equilibrium, as after a clamp lets go
  // of a hanging sheet, it can stall among wrinkles whose Hessian is indefinite), the sheet is
  // settled instead: see settle() (unless on_failure says kGiveUp).
  enum class OnFailure { kSettle, kGiveUp };
  SolveReport solve(const ClampSet& clamps, const std::vector<ClampPose>& poses, VecX& x,
                    const NewtonOptions& options = default_static_options(),
                    OnFailure on_failure = OnFailure::kSettle);

  // As solve(), for x an equilibrium whose clamps have just moved to `poses` (same clamps
  // engaged): starts Newton from the first-order predicted equilibrium instead of from x with
  // only the gripped patches moved, which would tear the sheet locally around each clamp.
  SolveReport solve_from_equilibrium(const ClampSet& clamps, const std::vector<ClampPose>& poses,
                                     VecX& x, const NewtonOptions& options = default_static_options());

  // Pseudo-transient continuation: a sequence of proximal steps, each the minimiser of
  //   E(x) + sum_i m_i |x_i - x_k,i|^2 / (2 tau^2)
  // (a backward-Euler step of length tau from rest), with tau growing while the steps are easy
  // and shrinking when one fails, until plain Newton converges from the last step. Every step
  // lowers the energy, so it reaches a stable equilibrium where Newton alone stalls; it is the
  // way the real sheet got there (it fell and came to rest). Spends at most 20x the Newton
  // iteration budget of `options` in all.
  SolveReport settle(const ClampSet& clamps, const std::vector<ClampPose>& poses, VecX& x,
                     const NewtonOptions& options = default_static_options());

 private:
  const ShellModel& model_;
  Objective objective_;
  NewtonSolver newton_;
  // Tangent predictions with the clamps' vertices held, for models whose clamps slip (their
  // own solves move every vertex): a second solver keeps both sparsity analyses.
  NewtonSolver held_predictor_;
  InertiaTerm proximal_;
  NewtonSolver settle_newton_;
};

}  // namespace twin
