#pragma once
// The linear algebra of one Newton iteration: assemble the Hessian over the free vertices and
// solve H d = -g, with the definiteness fix, and optionally reusing an older factorisation.
//
// Reuse (lagged preconditioning): the Cholesky factor of an earlier Hessian stays valid across
// iterations and across solves (successive time steps, continuation increments) as long as the
// sparsity pattern does. Each new system is solved by conjugate gradients preconditioned with
// that factor; only when CG needs too many iterations or meets negative curvature is the current
// Hessian factorised. As the factor ages CG needs more iterations; the factor is renewed when
// the last solve cost more than the average solve since the last factorisation, factorisation
// included (which minimises the average cost per solve when the cost of a solve grows with the
// factor's age). Measured on sheets of 1.5k-24k triangles, a numeric factorisation costs about
// as much as 11-20 CG iterations; `factorization_cost_in_cg_iterations` says how many.
//
// Background factorisation (with reuse; the implicit stepper's mode): the numeric factorisations
// run on a worker thread (background_factorizer.h), on the other core. The caller hands over
// the Hessian of where its next solve will be (submit_predicted: the stepper knows the next time
// step's start), and each solve is CG preconditioned with the last submitted factor: nearly its
// own matrix's, so CG needs 0-1 iterations. Each solve waits, if need be, for the last
// submitted factor, so that the result does not depend on timing. With no factor at all, or
// when CG misses its bound within max_cg_iterations (a fallback, counted), the solve has its own
// Hessian factorised on the worker and waits for it. (Preconditioning with an older finished factor instead, so as never to
// wait, measured worse in the cell: a factor a step old needs 7-9 CG iterations at 6k
// triangles, and each costs about a tenth of a factorisation.)
//
// Definiteness fix, when the matrix to factorise is not positive definite: the exact Hessian is
// replaced by its per-element projection (HessianMode::kProjected), and that, if still not
// positive definite (e.g. a sheet with too few clamps to stop rigid motion), by a diagonal shift
// growing 100x per try.

#include <deque>
#include <memory>

#include "twin/model/dof_map.h"
#include "twin/model/objective.h"
#include "twin/solvers/background_factorizer.h"
#include "twin/solvers/sparse_cholesky.h"

namespace twin {

struct LinearSolverOptions {
  bool reuse_factorization = false;
  int max_cg_iterations = 30;
  double cg_tolerance = 1e-2;  // relative residual of the linear system (the caller may lower it)
  double factorization_cost_in_cg_iterations = 15.0;
  // With reuse: factorisations on a worker thread, from submit_predicted (see above).
  bool background_factorization = false;
  // > 0: CG stops when the estimated error of every vertex's share of the solution (the
  // preconditioned residual M^-1 r, M ~ H: a vertex's 3-block norm) is below this (m), instead
  // of at the relative residual `tolerance`, which bounds no displacement.
  double cg_vertex_error_m = 0.0;
};

struct LinearSolveStats {
  int factorizations = 0;  // that this solve computed or waited for
  int fallbacks = 0;       // CG missed its tolerance with the reused factor
  double factor_wait_s = 0.0;  // background mode: time spent waiting for the worker
  int cg_iterations = 0;
  HessianMode mode_used = HessianMode::kProjected;
};

class NewtonLinearSolver {
 public:
  // Builds the sparsity pattern and symbolic analysis when the objective's terms or the fixed
  // vertices differ from the last call; otherwise keeps them and the current factor.
  void prepare(const Objective& objective, const DofMap& dofs);

  // step = -H^-1 g_free at x, H assembled in `mode` (or its fallbacks). False if no positive
  // definite system could be formed. `tolerance` is the CG relative tolerance to use.
  bool solve(const Objective& objective, const VecX& x, const VecX& g_free, HessianMode mode,
             const LinearSolverOptions& options, double tolerance, VecX& step,
             LinearSolveStats& stats);

  // Background mode: starts factorising the Hessian (in `mode`) at x on the worker, for the next
  // solves to precondition with. For a caller that knows where its next solve will be (the next
  // time step's start), so that solve gets a factor of nearly its own matrix.
  void submit_predicted(const Objective& objective, const VecX& x, HessianMode mode);

  // Forgets the factor (the next solve factorises), for example after a material change.
  void invalidate() {
    factor_valid_ = false;
    submitted_.clear();
  }

 private:
  bool factorize_current(const Objective& objective, const VecX& x, HessianMode& mode,
                         LinearSolveStats& stats);
  bool preconditioned_cg(const VecX& rhs, double tolerance, double vertex_error_m,
                         int max_iterations, VecX& solution, int& iterations) const;
  bool solve_with_background(const Objective& objective, const VecX& x, const VecX& g_free,
                             HessianMode mode, const LinearSolverOptions& options,
                             double tolerance, VecX& step, LinearSolveStats& stats);

  std::vector<const EnergyTerm*> terms_;
  std::vector<char> fixed_;
  std::unique_ptr<HessianPattern> pattern_;
  std::unique_ptr<SparseCholesky> cholesky_ = std::make_unique<SparseCholesky>();
  bool factor_valid_ = false;
  // Background mode: the worker (built on first use), and the tickets of the predicted
  // submissions not taken yet, oldest first.
  bool take_background(long ticket, LinearSolveStats& stats);
  std::unique_ptr<BackgroundFactorizer> background_;
  long tickets_ = 0;
  std::deque<long> submitted_;
  // The current factor's cycle: solves made with it and their cost, in CG iterations.
  int cycle_solves_ = 0;
  double cycle_cost_ = 0.0;
};

}  // namespace twin
