#include "twin/solvers/newton_linear_solver.h"

#include <algorithm>
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
  cholesky_->analyze(pattern_->matrix());
  if (background_) background_->reset(pattern_->matrix());
  submitted_.clear();
  terms_ = objective.terms();
  fixed_ = dofs.fixed_mask();
  factor_valid_ = false;
}

bool NewtonLinearSolver::factorize_current(const Objective& objective, const VecX& x,
                                           HessianMode& mode, LinearSolveStats& stats) {
  ++stats.factorizations;
  if (cholesky_->factorize(pattern_->matrix())) return true;
  if (mode == HessianMode::kExact) {
    mode = HessianMode::kProjected;
    objective.evaluate(x, nullptr, pattern_.get(), mode);
    ++stats.factorizations;
    if (cholesky_->factorize(pattern_->matrix())) return true;
  }
  const double diagonal = mean_abs_diagonal(pattern_->matrix());
  for (double mu = 1e-10; mu <= 1e2; mu *= 100.0) {
    ++stats.factorizations;
    if (cholesky_->factorize(pattern_->matrix(), mu * diagonal)) return true;
  }
  return false;
}

namespace {

// Largest 3-block norm of v (a vertex's share of a free-DOF vector).
double largest_vertex_norm(const VecX& v) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i + 3 <= v.size(); i += 3) largest = std::max(largest, v.segment<3>(i).norm());
  return largest;
}

}  // namespace

bool NewtonLinearSolver::preconditioned_cg(const VecX& rhs, double tolerance, double vertex_error_m,
                                           int max_iterations, VecX& solution, int& iterations) const {
  const auto h = pattern_->matrix().selfadjointView<Eigen::Upper>();
  const double target = tolerance * rhs.norm();
  solution = cholesky_->solve(rhs);  // the preconditioned first guess
  VecX r = rhs - h * solution;
  VecX z = cholesky_->solve(r);
  VecX p = z;
  double rz = r.dot(z);
  auto converged = [&] {
    return vertex_error_m > 0.0 ? largest_vertex_norm(z) <= vertex_error_m : r.norm() <= target;
  };
  for (iterations = 0; iterations < max_iterations; ++iterations) {
    if (converged()) return true;
    const VecX hp = h * p;
    const double curvature = p.dot(hp);
    if (!(curvature > 0.0)) return false;  // negative curvature or breakdown
    const double alpha = rz / curvature;
    solution += alpha * p;
    r -= alpha * hp;
    z = cholesky_->solve(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return converged();
}

bool NewtonLinearSolver::solve(const Objective& objective, const VecX& x, const VecX& g_free,
                               HessianMode mode, const LinearSolverOptions& options,
                               double tolerance, VecX& step, LinearSolveStats& stats) {
  objective.evaluate(x, nullptr, pattern_.get(), mode);
  stats.mode_used = mode;
  if (options.reuse_factorization && options.background_factorization) {
    return solve_with_background(objective, x, g_free, mode, options, tolerance, step, stats);
  }
  if (options.reuse_factorization && factor_valid_) {
    int iterations = 0;
    const bool ok = preconditioned_cg(-g_free, tolerance, options.cg_vertex_error_m,
                                      options.max_cg_iterations, step, iterations);
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
  step = -cholesky_->solve(g_free);
  return step.allFinite();
}

void NewtonLinearSolver::submit_predicted(const Objective& objective, const VecX& x, HessianMode mode) {
  if (!background_) {
    background_ = std::make_unique<BackgroundFactorizer>();
    background_->reset(pattern_->matrix());
  }
  objective.evaluate(x, nullptr, pattern_.get(), mode);
  submitted_.push_back(++tickets_);
  background_->submit(pattern_->matrix(), tickets_);
}

bool NewtonLinearSolver::take_background(long ticket, LinearSolveStats& stats) {
  const BackgroundFactorizer::Taken taken = background_->take(cholesky_, ticket);
  stats.factor_wait_s += taken.waited_s;
  while (!submitted_.empty() && submitted_.front() <= ticket) submitted_.pop_front();
  if (!taken.ok) return false;
  factor_valid_ = true;
  return true;
}

bool NewtonLinearSolver::solve_with_background(const Objective& objective, const VecX& x,
                                               const VecX& g_free, HessianMode mode,
                                               const LinearSolverOptions& options, double tolerance,
                                               VecX& step, LinearSolveStats& stats) {
  if (!background_) {
    background_ = std::make_unique<BackgroundFactorizer>();
    background_->reset(pattern_->matrix());
  }
  auto cg_solves = [&] {
    int iterations = 0;
    const bool ok = preconditioned_cg(-g_free, tolerance, options.cg_vertex_error_m,
                                      options.max_cg_iterations, step, iterations);
    stats.cg_iterations += iterations;
    // On an indefinite H, CG can converge without meeting negative curvature and still return
    // an ascent direction; only a descent direction is taken from it.
    return ok && step.allFinite() && step.dot(g_free) < 0.0;
  };
  // The factor to precondition with: the last submitted (the caller predicted it for this
  // solve), waited for.
  if (!submitted_.empty()) take_background(submitted_.back(), stats);
  if (factor_valid_) {
    if (cg_solves()) return true;
    ++stats.fallbacks;
  }
  // This solve's own Hessian, on the worker (which is idle by now), waited for.
  submitted_.clear();
  const long own = ++tickets_;
  background_->submit(pattern_->matrix(), own);
  ++stats.factorizations;
  if (take_background(own, stats)) {
    step = -cholesky_->solve(g_free);
    if (step.allFinite()) return true;
  }
  // Not positive definite: the definiteness fix, here.
  factor_valid_ = factorize_current(objective, x, mode, stats);
  stats.mode_used = mode;
  if (!factor_valid_) return false;
  step = -cholesky_->solve(g_free);
  return step.allFinite();
}

}  // namespace twin
