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
// Definiteness fix, when the matrix to factorise is not positive definite: the exact Hessian is
// replaced by its per-element projection (HessianMode::kProjected), and that, if still not
// positive definite (e.g. a sheet with too few clamps to stop rigid motion), by a diagonal shift
// growing 100x per try.

#include <memory>

#include "twin/model/dof_map.h"
#include "twin/model/objective.h"
#include "twin/solvers/sparse_cholesky.h"

namespace twin {

struct LinearSolverOptions {
  bool reuse_factorization = false;
  int max_cg_iterations = 30;
  double cg_tolerance = 1e-2;  // relative residual of the linear system (the caller may lower it)
  double factorization_cost_in_cg_iterations = 15.0;
};

struct LinearSolveStats {
  int factorizations = 0;
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

  // Forgets the factor (the next solve factorises), for example after a material change.
  void invalidate() { factor_valid_ = false; }

 private:
  bool factorize_current(const Objective& objective, const VecX& x, HessianMode& mode,
                         LinearSolveStats& stats);
  bool preconditioned_cg(const VecX& rhs, double tolerance, int max_iterations, VecX& solution,
                         int& iterations) const;

  std::vector<const EnergyTerm*> terms_;
  std::vector<char> fixed_;
  std::unique_ptr<HessianPattern> pattern_;
  SparseCholesky cholesky_;
  bool factor_valid_ = false;
  // The current factor's cycle: solves made with it and their cost, in CG iterations.
  int cycle_solves_ = 0;
  double cycle_cost_ = 0.0;
};

}  // namespace twin
