#include "twin/solvers/newton_linear_solver.h"

#include <cmath>

namespace twin {
namespace {

double mean_abs_diagonal(const HessianPattern::Matrix& upper) {
  double sum = 0.0;
  for (int j = 0; j < upper.outerSize(); ++j) {
    // The diagonal entry is the last one stored in each column of the upper triangle.
    sum += std::abs(upper.valuePtr()[upper.outerIndexPtr()[j + 1] - 1]);
  }
  return upper.outerSize() > 0 ? sum / upper.outerSize() : 1.0;
}

}  // namespace

void NewtonLinearSolver::prepare(const Objective& objective, const DofMap& dofs) {
  if (pattern_ && terms_ == objective.terms() && fixed_ == dofs.fixed_mask()) return;
  pattern_ = std::make_unique<HessianPattern>(dofs, objective.stencils());
  cholesky_.analyze(pattern_->matrix());
  terms_ = objective.terms();
  fixed_ = dofs.fixed_mask();
  factor_valid_ = false;
}

bool NewtonLinearSolver::factorize_current(const Objective& objective, const VecX& x,
                                           HessianMode& mode, LinearSolveStats& stats) {
  ++stats.factorizations;
  if (cholesky_.factorize(pattern_->matrix())) return true;
  if (mode == HessianMode::kExact) {
    mode = HessianMode::kProjected;
    objective.evaluate(x, nullptr, pattern_.get(), mode);
    ++stats.factorizations;
    if (cholesky_.factorize(pattern_->matrix())) return true;
  }
  const double diagonal = mean_abs_diagonal(pattern_->matrix());
  for (double mu = 1e-10; mu <= 1e2; mu *= 100.0) {
    ++stats.factorizations;
    if (cholesky_.factorize(pattern_->matrix(), mu * diagonal)) return true;
  }
  return false;
}

bool NewtonLinearSolver::preconditioned_cg(const VecX& rhs, double tolerance, int max_iterations,
                                           VecX& solution, int& iterations) const {
  const auto h = pattern_->matrix().selfadjointView<Eigen::Upper>();
  const double target = tolerance * rhs.norm();
  solution = cholesky_.solve(rhs);  // the preconditioned first guess
  VecX r = rhs - h * solution;
  VecX z = cholesky_.solve(r);
  VecX p = z;
  double rz = r.dot(z);
  for (iterations = 0; iterations < max_iterations; ++iterations) {
    if (r.norm() <= target) return true;
    const VecX hp = h * p;
    const double curvature = p.dot(hp);
    if (!(curvature > 0.0)) return false;  // negative curvature or breakdown
    const double alpha = rz / curvature;
    solution += alpha * p;
    r -= alpha * hp;
    z = cholesky_.solve(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return r.norm() <= target;
}

bool NewtonLinearSolver::solve(const Objective& objective, const VecX& x, const VecX& g_free,
                               HessianMode mode, const LinearSolverOptions& options,
                               double tolerance, VecX& step, LinearSolveStats& stats) {
  objective.evaluate(x, nullptr, pattern_.get(), mode);
  stats.mode_used = mode;
  if (options.reuse_factorization && factor_valid_) {
    int iterations = 0;
    const bool ok = preconditioned_cg(-g_free, tolerance, options.max_cg_iterations, step, iterations);
    stats.cg_iterations += iterations;
    // One preconditioner application plus one per iteration.
    const double cost = 1.0 + iterations;
    ++cycle_solves_;
    cycle_cost_ += cost;
    // On an indefinite H, CG can converge without meeting negative curvature and still return
    // an ascent direction; only a descent direction is taken from it.
    if (ok && step.allFinite() && step.dot(g_free) < 0.0) {
      // This solve cost more than the cycle's average: the factor has aged; renew it next time.
      if (cost > cycle_cost_ / cycle_solves_) factor_valid_ = false;
      return true;
    }
  }
  factor_valid_ = factorize_current(objective, x, mode, stats);
  stats.mode_used = mode;
  if (!factor_valid_) return false;
  cycle_solves_ = 1;
  cycle_cost_ = options.factorization_cost_in_cg_iterations + 1.0;
  step = -cholesky_.solve(g_free);
  return step.allFinite();
}

}  // namespace twin
