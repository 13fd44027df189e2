#include "twin/newton_solver.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace twin {
namespace {

using Clock = std::chrono::steady_clock;

double mean_abs_diagonal(const HessianPattern::Matrix& upper) {
  double sum = 0.0;
  for (int j = 0; j < upper.outerSize(); ++j) {
    // The diagonal entry is the last one stored in each column of the upper triangle.
    sum += std::abs(upper.valuePtr()[upper.outerIndexPtr()[j + 1] - 1]);
  }
  return upper.outerSize() > 0 ? sum / upper.outerSize() : 1.0;
}

}  // namespace

VecX gather_free(const DofMap& dofs, const VecX& full) {
  VecX out(dofs.free_dof_count());
  for (int v = 0; v < dofs.vertex_count(); ++v) {
    const int f = dofs.free_index(v);
    if (f >= 0) out.segment<3>(3 * f) = full.segment<3>(3 * v);
  }
  return out;
}

double free_norm(const DofMap& dofs, const VecX& full) { return gather_free(dofs, full).norm(); }

NewtonSolver::NewtonSolver() = default;
NewtonSolver::~NewtonSolver() = default;

void NewtonSolver::prepare(const Objective& objective, const DofMap& dofs) {
  if (pattern_ && cached_terms_ == objective.terms() && cached_fixed_ == dofs.fixed_mask()) return;
  pattern_ = std::make_unique<HessianPattern>(dofs, objective.stencils());
  cholesky_.analyze(pattern_->matrix());
  cached_terms_ = objective.terms();
  cached_fixed_ = dofs.fixed_mask();
}

SolveReport NewtonSolver::minimize(const Objective& objective, const DofMap& dofs,
                                   double force_scale_N, VecX& x, const NewtonOptions& options) {
  const auto start = Clock::now();
  SolveReport report;
  const VecX x_entry = x;
  auto finish = [&](SolveStatus status, std::string message) {
    report.status = status;
    report.message = std::move(message);
    report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (status != SolveStatus::kConverged) x = x_entry;
    return report;
  };
  if (dofs.free_vertex_count() == 0) {
    report.energy_J = objective.evaluate(x, nullptr, nullptr, HessianMode::kExact);
    return finish(SolveStatus::kConverged, "no free vertex");
  }
  prepare(objective, dofs);
  HessianPattern& pattern = *pattern_;
  const double scale = force_scale_N > 0.0 ? force_scale_N : 1.0;

  VecX grad(x.size()), trial(x.size());
  for (report.iterations = 0;; ++report.iterations) {
    // Residual test on the current state, with the gradient from this iteration's assembly.
    double energy = objective.evaluate(x, &grad, nullptr, HessianMode::kProjected);
    const VecX g = gather_free(dofs, grad);
    report.energy_J = energy;
    report.residual = g.norm() / scale;
    if (!std::isfinite(energy) || !g.allFinite()) {
      return finish(SolveStatus::kNonFinite, fmt::format("at iteration {}", report.iterations));
    }
    if (report.residual < options.residual_tolerance) return finish(SolveStatus::kConverged, "");
    if (report.iterations >= options.max_iterations) {
      return finish(SolveStatus::kMaxIterations, fmt::format("residual {:.2e} > {:.2e}",
                                                             report.residual,
                                                             options.residual_tolerance));
    }

    // Newton direction with the definiteness fix.
    HessianMode mode = report.residual < options.exact_hessian_below ? HessianMode::kExact
                                                                      : HessianMode::kProjected;
    objective.evaluate(x, nullptr, &pattern, mode);
    bool factored = false;
    const int factorizations_before = report.factorizations;
    ++report.factorizations;
    if (cholesky_.factorize(pattern.matrix())) {
      factored = true;
    } else if (mode == HessianMode::kExact) {
      mode = HessianMode::kProjected;
      objective.evaluate(x, nullptr, &pattern, mode);
      ++report.factorizations;
      factored = cholesky_.factorize(pattern.matrix());
    }
    if (!factored) {
      const double diagonal = mean_abs_diagonal(pattern.matrix());
      for (double mu = 1e-10; mu <= 1e2 && !factored; mu *= 100.0) {
        ++report.factorizations;
        factored = cholesky_.factorize(pattern.matrix(), mu * diagonal);
      }
    }
    if (!factored) return finish(SolveStatus::kIndefinite, "");
    const VecX step = -cholesky_.solve(g);
    if (!step.allFinite()) return finish(SolveStatus::kNonFinite, "in the Newton step");
    double slope = g.dot(step);  // J, negative for a descent direction
    if (!(slope < 0.0)) return finish(SolveStatus::kLineSearchFailed, "not a descent direction");

    // Cap the largest vertex move, then backtrack until the energy decreases enough.
    double alpha = 1.0;
    double largest = 0.0;
    for (int f = 0; f < dofs.free_vertex_count(); ++f) largest = std::max(largest, step.segment<3>(3 * f).norm());
    if (largest > options.max_step_m) alpha = options.max_step_m / largest;
    // Energy differences below this are rounding noise of the total energy.
    const double noise = 1e-13 * std::max(1.0, std::abs(energy));
    auto energy_at = [&](double a, VecX& out) {
      out = x;
      for (int v = 0; v < dofs.vertex_count(); ++v) {
        const int f = dofs.free_index(v);
        if (f >= 0) out.segment<3>(3 * v) += a * step.segment<3>(3 * f);
      }
      const double e = objective.evaluate(out, nullptr, nullptr, HessianMode::kProjected);
      return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
    };
    double trial_energy = energy_at(alpha, trial);
    int halvings = 0;
    while (!(trial_energy <= energy + options.armijo * alpha * slope + noise)) {
      if (++halvings > options.max_halvings) {
        return finish(SolveStatus::kLineSearchFailed,
                      fmt::format("at iteration {}, residual {:.2e}", report.iterations,
                                  report.residual));
      }
      alpha *= 0.5;
      trial_energy = energy_at(alpha, trial);
    }
    // A full step that was accepted may still stop short: from a flat sheet the load is carried
    // by membrane stretch, a cubic response whose Newton steps undershoot by about 3x. Doubling
    // while the energy keeps falling costs energy evaluations instead of factorisations.
    if (halvings == 0 && options.max_extrapolation > 1.0) {
      VecX further(x.size());
      for (double a = 2.0 * alpha; a <= options.max_extrapolation * alpha + 1e-12; a *= 2.0) {
        if (a * largest > options.max_step_m) break;
        const double e = energy_at(a, further);
        if (!(e < trial_energy - noise)) break;
        trial_energy = e;
        trial.swap(further);
        alpha = a;
      }
    }
    x.swap(trial);
    if (options.on_iteration) {
      options.on_iteration({report.iterations, report.residual, energy, alpha, alpha * largest,
                            mode == HessianMode::kExact,
                            report.factorizations - factorizations_before});
    }
  }
}

}  // namespace twin
