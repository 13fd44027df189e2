#pragma once
// A quasi-Newton relaxation towards the nearest equilibrium whose iterations do not each
// assemble and factorise the Hessian: limited-memory BFGS whose initial inverse Hessian is one
// Cholesky factorisation of the Hessian (exact, or shifted by mu M where that is not positive
// definite, as damped_newton.h does), kept for many iterations. Each iteration costs a solve with
// that factor and one or two energy and gradient evaluations: on a spline patch of 100,000
// unknowns about a tenth of a Newton iteration. Where the factor grows stale (a line search that
// fails, or a step that is no descent) the Hessian is factorised again at the current state.
//
// It is meant for re-equilibrating a state already near an equilibrium (a shape carried to a
// finer patch, a jaw moved by an increment): steps are backtracked until the energy falls and
// cut to a trust radius, so it moves downhill as Newton's method does, and hands over to
// damped_newton for the last digits (quadratic convergence there). It is no model of a fall:
// an overdamped motion that picks a branch stays with damped_newton's pseudo-time.

#include <string>

#include "sim_hw/real_sheet/damped_newton.h"

namespace sim_hw::spline_shell {

struct LbfgsOptions {
  double tolerance_N = 1e-9;  // stop (converged) when the largest force is below this
  int max_iterations = 400;
  int memory = 8;             // pairs (s, y) kept
  int refactor_every = 10;    // iterations on one factor at most
  double step_limit_m = 0.01;  // no point moves further in one step
  bool trace = false;
};

struct LbfgsReport {
  bool converged = false;
  int iterations = 0, factorizations = 0, evaluations = 0;
  double max_force_N = 0, energy_J = 0;
  std::string message;  // why it stopped short
};

// Moves the problem's state downhill; never leaves it higher in energy than it started.
LbfgsReport preconditioned_lbfgs(real_sheet::NewtonProblem& problem, real_sheet::BlockSparseMatrix& H,
                                 real_sheet::Cholesky& cholesky, const Eigen::VectorXd& metric,
                                 const LbfgsOptions& options);

}  // namespace sim_hw::spline_shell
