#pragma once
// Minimises an Objective over the free vertices by Newton's method with a backtracking line
// search. Used for static equilibrium and for each implicit time step.
//
// Far from the solution the Hessian is the per-element positive semi-definite projection
// (HessianMode::kProjected); once the residual is below `exact_hessian_below` the exact Hessian
// gives quadratic convergence. Linear algebra, the definiteness fix and the reuse of
// factorisations are in newton_linear_solver.h. Any failure restores x to its value on entry.

#include <functional>
#include <limits>

#include "twin/solvers/newton_linear_solver.h"
#include "twin/solvers/solve_report.h"

namespace twin {

// What one iteration did, for progress output and diagnosis.
struct NewtonIteration {
  int iteration = 0;
  double residual = 0.0;
  double energy_J = 0.0;
  double step_length = 0.0;     // alpha finally taken
  double largest_move_m = 0.0;  // of any vertex in the taken step
  bool exact_hessian = false;
  int factorizations = 0;       // in this iteration
  int cg_iterations = 0;        // in this iteration
};

struct NewtonOptions {
  int max_iterations = 200;
  double residual_tolerance = 1e-8;    // ||free force|| / force scale
  // A residual above the tolerance but below this counts as converged when the Newton step's
  // predicted energy change is below the energy's rounding noise (see newton_solver.cc).
  double round_off_residual = 1e-3;
  double exact_hessian_below = 1e-3;   // residual under which the exact Hessian is used
  double max_step_m = std::numeric_limits<double>::infinity();  // cap on a vertex's move per step
  double armijo = 1e-4;                // sufficient-decrease constant
  int max_halvings = 40;
  double max_extrapolation = 8.0;      // largest multiple of an accepted full step tried
  // Fixed-budget mode: reaching max_iterations with every step having lowered the objective is
  // a usable result (SolveStatus::kIterationBudget), as in a linearised implicit step.
  bool accept_iteration_budget = false;
  LinearSolverOptions linear;
  std::function<void(const NewtonIteration&)> on_iteration;  // optional progress callback
};

class NewtonSolver {
 public:
  // x: on entry the start (fixed vertices already at their targets); on success the minimiser.
  // force_scale_N sets the residual's unit (for example the sheet's weight on the free
  // vertices). Never throws for numerical trouble; read the report instead.
  SolveReport minimize(const Objective& objective, const DofMap& dofs, double force_scale_N,
                       VecX& x, const NewtonOptions& options);
  // First-order continuation predictor. x_old is an equilibrium; x_moved equals x_old except
  // that the vertices fixed in `dofs` have been moved to new held positions. Returns x_moved
  // with the free vertices moved by the linear response  K_ff dx_f = -K_fc dx_c  (K the Hessian
  // at x_old; K_fc dx_c by a directional finite difference of the forces), which is where the
  // new equilibrium is to first order. Returns x_moved unchanged if the system cannot be solved.
  VecX tangent_predictor(const Objective& objective, const DofMap& dofs, const VecX& x_old,
                         const VecX& x_moved);
  // With background factorisation (newton_linear_solver.h): starts factorising the projected
  // Hessian at x, where the next minimize() over this objective and dofs will start.
  void prefactorize(const Objective& objective, const DofMap& dofs, const VecX& x) {
    if (dofs.free_vertex_count() == 0) return;
    linear_.prepare(objective, dofs);
    linear_.submit_predicted(objective, x, HessianMode::kProjected);
  }
  // Drops the reusable factorisation (after a material change, say).
  void invalidate_factorization() { linear_.invalidate(); }

 private:
  NewtonLinearSolver linear_;
};

// Free part of a full 3n vector, in free-DOF order.
VecX gather_free(const DofMap& dofs, const VecX& full);

}  // namespace twin
