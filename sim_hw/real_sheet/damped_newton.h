#pragma once
// A damped Newton method for a potential over a state that moves by steps dx: each iteration
// solves (H + mu M) dx = -g, with M a per-unknown metric (masses), and backtracks along dx
// until the energy falls. mu (1/s^2) is a pseudo-time damping: large, the step is a short
// overdamped motion under the forces (how a released or folding sheet really moves, and what
// picks its branch); zero, it is Newton's step. mu shrinks after full steps and grows after
// failed ones. H is the exact Hessian when mu is zero and it is positive definite, the
// projected one otherwise. Converged when every block's force is below the tolerance, or a
// Newton step moves nothing any more. On failure the state is put back as it was.
//
// The lab's plate (equilibrium_solver.h, with jaws that turn) and the reference's spline shell
// (sim_hw/spline_shell) both minimise through it: each says what its state is and how it moves.

#include <string>

#include <Eigen/Core>

#include "sim_hw/real_sheet/block_sparse.h"
#include "sim_hw/real_sheet/cholesky.h"
#include "sim_hw/real_sheet/membrane_q4.h"  // Hessian

namespace sim_hw::real_sheet {

using VecX = Eigen::VectorXd;

// What the method minimises. The state is the problem's own; dx (size of the Hessian) moves it.
class NewtonProblem {
 public:
  virtual ~NewtonProblem() = default;
  // Energy (J) at the state moved by alpha dx (dx null: the state itself); the gradient (N)
  // when g is non-null (sized by the problem).
  virtual double energy_at(const VecX* dx, double alpha, VecX* g) const = 0;
  // The Hessian (N/m) at the state into H (its values replaced).
  virtual void hessian(BlockSparseMatrix& H, Hessian kind) const = 0;
  virtual void move(const VecX& dx, double alpha) = 0;
  // The largest displacement (m) of a point of the sheet along dx: the trust radius's measure.
  virtual double longest_move_m(const VecX& dx) const = 0;
  // The largest force of one block of the gradient (a node's or control's N, a jaw's N*m).
  virtual double largest_force_N(const VecX& g) const;
  virtual void save() = 0;
  virtual void restore() = 0;
};

struct DampedNewtonOptions {
  double tolerance_N = 1e-9;   // converged when the largest force is below this
  double step_tolerance_m = 1e-10;
  int max_iterations = 400;
  double initial_damping_1_s2 = 0.0;
  bool keep_on_limit = false;
  bool projected_hessian = false;
  double step_limit_m = 0.05;
  // Where the exact Hessian is not positive definite, try it shifted by mu M (Levenberg-Marquardt,
  // mu growing 8-fold from max(1, 4 mu), up to six times) before the projected one: near an
  // equilibrium with compressed regions the projected Hessian converges only linearly.
  bool shifted_exact = false;
  bool trace = false;  // one line per iteration on stderr
};

struct DampedNewtonReport {
  bool converged = false;
  bool budget_used = false;
  int iterations = 0, factorizations = 0;
  double max_force_N = 0;
  double energy_J = 0;
  std::string message;
};

// H must hold the problem's Hessian pattern; metric (kg, or kg m^2 for a rotation) is per unknown.
DampedNewtonReport damped_newton(NewtonProblem& problem, BlockSparseMatrix& H, Cholesky& cholesky, const VecX& metric,
                                 const DampedNewtonOptions& options);

}  // namespace sim_hw::real_sheet
