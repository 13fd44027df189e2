#include "twin/solvers/newton_solver.h"
#include "twin/base/cancellation.h"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

namespace twin {

VecX gather_free(const DofMap& dofs, const VecX& full) {
  VecX out(dofs.free_dof_count());
  for (int v = 0; v < dofs.vertex_count(); ++v) {
    const int f = dofs.free_index(v);
    if (f >= 0) out.segment<3>(3 * f) = full.segment<3>(3 * v);
  }
  return out;
}

VecX NewtonSolver::tangent_predictor(const Objective& objective, const DofMap& dofs,
                                     const VecX& x_old, const VecX& x_moved) {
  const VecX moved = x_moved - x_old;
  const double largest = moved.cwiseAbs().maxCoeff();
  if (dofs.free_vertex_count() == 0 || !(largest > 0.0)) return x_moved;
  linear_.prepare(objective, dofs);
  // K dx_c by central differences along dx_c, over a 1e-7 m perturbation: accurate to ~1e-7
  // relative for these smooth energies, far better than the predictor needs.
  const double h = 1e-7 / largest;
  VecX g_plus(x_old.size()), g_minus(x_old.size());
  objective.evaluate(x_old + h * moved, &g_plus, nullptr, HessianMode::kExact);
  objective.evaluate(x_old - h * moved, &g_minus, nullptr, HessianMode::kExact);
  const VecX coupling = gather_free(dofs, g_plus - g_minus) / (2.0 * h);
  if (!coupling.allFinite()) return x_moved;
  VecX response;
  LinearSolveStats stats;
  LinearSolverOptions linear;
  if (!linear_.solve(objective, x_old, coupling, HessianMode::kExact, linear, 1e-6, response, stats)) {
    return x_moved;
  }
  VecX predicted = x_moved;
  for (int v = 0; v < dofs.vertex_count(); ++v) {
    const int f = dofs.free_index(v);
    if (f >= 0) predicted.segment<3>(3 * v) += response.segment<3>(3 * f);
  }
  return predicted;
}

SolveReport NewtonSolver::minimize(const Objective& objective, const DofMap& dofs,
                                   double force_scale_N, VecX& x, const NewtonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SolveReport report;
  const VecX x_entry = x;
  auto finish = [&](SolveStatus status, std::string message) {
    report.status = status;
    report.message = std::move(message);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (status != SolveStatus::kConverged && status != SolveStatus::kIterationBudget) x = x_entry;
    return report;
  };
  if (dofs.free_vertex_count() == 0) {
    report.energy_J = objective.evaluate(x, nullptr, nullptr, HessianMode::kExact);
    return finish(SolveStatus::kConverged, "no free vertex");
  }
  linear_.prepare(objective, dofs);
  const double scale = force_scale_N > 0.0 ? force_scale_N : 1.0;

  // Position after a step of length a along `step`, and the objective there.
  VecX step, grad(x.size()), trial(x.size()), further(x.size());
  auto move = [&](double a, VecX& out) {
    out = x;
    for (int v = 0; v < dofs.vertex_count(); ++v) {
      const int f = dofs.free_index(v);
      if (f >= 0) out.segment<3>(3 * v) += a * step.segment<3>(3 * f);
    }
  };
  auto energy_at = [&](const VecX& y, VecX* g) {
    const double e = objective.evaluate(y, g, nullptr, HessianMode::kProjected);
    return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
  };

  double energy = energy_at(x, &grad);
  double best_residual = std::numeric_limits<double>::infinity();
  int stalled = 0;
  for (report.iterations = 0;; ++report.iterations) {
    const VecX g = gather_free(dofs, grad);
    report.energy_J = energy;
    report.residual = g.norm() / scale;
    if (!std::isfinite(energy) || !g.allFinite()) {
      return finish(SolveStatus::kNonFinite, fmt::format("at iteration {}", report.iterations));
    }
    if (report.residual < options.residual_tolerance) return finish(SolveStatus::kConverged, "");
    if (cancellation_requested()) return finish(SolveStatus::kCancelled, fmt::format("at iteration {}", report.iterations));
    if (report.iterations >= options.max_iterations) {
      if (options.accept_iteration_budget && report.iterations > 0) {
        return finish(SolveStatus::kIterationBudget, "");
      }
      return finish(SolveStatus::kMaxIterations,
                    fmt::format("residual {:.2e} > {:.2e}", report.residual, options.residual_tolerance));
    }

    // Newton direction. CG tolerance tightens with the residual (superlinear inexact Newton).
    const HessianMode mode = report.residual < options.exact_hessian_below ? HessianMode::kExact
                                                                           : HessianMode::kProjected;
    LinearSolveStats stats;
    const double cg_tolerance = std::min(options.linear.cg_tolerance, std::sqrt(report.residual));
    const bool solved = linear_.solve(objective, x, g, mode, options.linear, cg_tolerance, step, stats);
    report.factorizations += stats.factorizations;
    report.cg_iterations += stats.cg_iterations;
    report.fallbacks += stats.fallbacks;
    report.factor_wait_s += stats.factor_wait_s;
    if (!solved) return finish(SolveStatus::kIndefinite, "");
    const double slope = g.dot(step);  // J, negative for a descent direction
    if (!(slope < 0.0)) return finish(SolveStatus::kLineSearchFailed, "not a descent direction");
    // Energy differences below this are rounding noise of the total energy.
    const double noise = 1e-13 * std::max(1.0, std::abs(energy));
    // A stiff membrane leaves force noise of about Y * 1e-17 / h per vertex from rounded
    // positions. Once the energy no longer resolves a Newton step and three such steps in a row
    // have not halved the best residual, what is left is that noise: converged as far as
    // doubles allow.
    if (-slope < noise && report.residual > 0.5 * best_residual) {
      if (++stalled >= 3 && report.residual < options.round_off_residual) {
        return finish(SolveStatus::kConverged,
                      fmt::format("at the round-off floor (residual {:.2e})", report.residual));
      }
    } else {
      stalled = 0;
    }
    best_residual = std::min(best_residual, report.residual);

    // Cap the largest vertex move, then backtrack until the energy decreases enough.
    double largest = 0.0;
    for (int f = 0; f < dofs.free_vertex_count(); ++f) largest = std::max(largest, step.segment<3>(3 * f).norm());
    double alpha = largest > options.max_step_m ? options.max_step_m / largest : 1.0;
    move(alpha, trial);
    VecX trial_grad(x.size());
    double trial_energy = energy_at(trial, &trial_grad);
    int halvings = 0;
    while (!(trial_energy <= energy + options.armijo * alpha * slope + noise)) {
      if (++halvings > options.max_halvings) {
        return finish(SolveStatus::kLineSearchFailed,
                      fmt::format("at iteration {}, residual {:.2e}", report.iterations, report.residual));
      }
      alpha *= 0.5;
      move(alpha, trial);
      trial_energy = energy_at(trial, nullptr);
    }
    // A full step that was accepted may still stop short: from a flat sheet the load is carried
    // by membrane stretch, a cubic response whose Newton steps undershoot by about 3x. Doubling
    // while the energy keeps falling costs energy evaluations instead of factorisations.
    bool gradient_current = halvings == 0;
    if (halvings == 0) {
      for (double a = 2.0 * alpha; a <= options.max_extrapolation * alpha + 1e-12; a *= 2.0) {
        if (a * largest > options.max_step_m) break;
        move(a, further);
        const double e = energy_at(further, nullptr);
        if (!(e < trial_energy - noise)) break;
        trial_energy = e;
        trial.swap(further);
        alpha = a;
        gradient_current = false;
      }
    }
    x.swap(trial);
    energy = trial_energy;
    if (gradient_current) {
      grad.swap(trial_grad);
    } else {
      energy = energy_at(x, &grad);
    }
    if (options.on_iteration) {
      options.on_iteration({report.iterations, report.residual, energy, alpha, alpha * largest,
                            stats.mode_used == HessianMode::kExact, stats.factorizations,
                            stats.cg_iterations});
    }
  }
}

}  // namespace twin
