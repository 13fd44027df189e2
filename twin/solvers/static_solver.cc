#include "twin/solvers/static_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace twin {

NewtonOptions default_static_options() {
  NewtonOptions options;
  options.max_iterations = 200;
  options.residual_tolerance = 1e-8;
  // From a flat sheet the first Newton steps predict sags of metres (only bending resists);
  // a cap of a few centimetres per vertex per iteration keeps the line search short.
  options.max_step_m = 0.05;
  // Measured on the composite five-stage scenario: the exact Hessian from residual 1 saves
  // ~15 % of the iterations over 1e-3; reusing factorisations (lagged-preconditioner CG) costs
  // 10-45 % more time, because the Hessian changes too much between static iterations.
  options.exact_hessian_below = 1.0;
  options.linear.reuse_factorization = false;
  return options;
}

StaticSolver::StaticSolver(const ShellModel& model)
    : model_(model), objective_(model.potential_terms()), proximal_(model.vertex_masses_kg(), 0.0) {}

double free_weight_N(const ShellModel& model, const DofMap& dofs) {
  double sum = 0.0;
  const double g = model.gravity().gravity().norm();
  for (int v = 0; v < dofs.vertex_count(); ++v) {
    if (!dofs.is_fixed(v)) sum += std::pow(model.vertex_masses_kg()[v] * g, 2);
  }
  return std::sqrt(sum);
}

SolveReport StaticSolver::solve(const ClampSet& clamps, const std::vector<ClampPose>& poses,
                                VecX& x, const NewtonOptions& options, OnFailure on_failure) {
  const DofMap dofs = model_.hold_clamps(clamps, poses);
  VecX trial = x;
  clamps.hold(poses, trial);
  SolveReport report = newton_.minimize(objective_, dofs, free_weight_N(model_, dofs), trial, options);
  if (report.usable()) {
    x.swap(trial);
    return report;
  }
  if (on_failure == OnFailure::kGiveUp) return report;
  report.append(settle(clamps, poses, x, options));
  return report;
}

SolveReport StaticSolver::settle(const ClampSet& clamps, const std::vector<ClampPose>& poses,
                                 VecX& x, const NewtonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const DofMap dofs = model_.hold_clamps(clamps, poses);
  const double force_scale_N = free_weight_N(model_, dofs);
  VecX current = x;
  clamps.hold(poses, current);
  proximal_.set_masses(model_.vertex_masses_kg());  // the density may have changed
  std::vector<const EnergyTerm*> terms = model_.potential_terms();
  terms.push_back(&proximal_);
  const Objective proximal_objective(std::move(terms));

  // A proximal step only has to lower the energy; it need not be solved tightly.
  NewtonOptions step_options = options;
  step_options.max_iterations = 25;
  step_options.residual_tolerance = 1e-5;
  step_options.on_iteration = nullptr;
  step_options.exact_hessian_below = std::numeric_limits<double>::infinity();
  // The final polish from a settled shape needs few iterations; a stall costs little.
  NewtonOptions polish_options = options;
  polish_options.max_iterations = 40;

  SolveReport report;
  report.status = SolveStatus::kMaxIterations;
  auto account = [&](const SolveReport& r) {
    report.iterations += r.iterations;
    report.factorizations += r.factorizations;
    report.residual = r.residual;
    report.energy_J = r.energy_J;
  };
  // tau (s): 20 ms lets a sheet at rest fall 2 mm in the first step.
  double tau_s = 0.02;
  constexpr double kShortestTau_s = 1e-4, kLongestTau_s = 1e3;
  constexpr int kMaxSteps = 300;
  int steps_until_polish = 0;  // after a failed polish, settle a little more first
  // The caller's Newton budget bounds the whole settling, scaled: settling takes many cheap
  // steps (measured: up to ~1400 iterations for a released 6000-triangle sheet).
  const int iteration_budget = 20 * options.max_iterations;
  for (int step = 0; step < kMaxSteps && report.iterations < iteration_budget; ++step) {
    proximal_.set_step(current, VecX::Zero(current.size()), tau_s);
    VecX next = current;
    const SolveReport r = settle_newton_.minimize(proximal_objective, dofs, force_scale_N, next, step_options);
    account(r);
    if (!r.usable()) {
      tau_s /= 4.0;
      if (tau_s < kShortestTau_s) {
        report.status = r.status;
        report.message = "settling stalled: " + r.message;
        break;
      }
      continue;
    }
    const double largest_move_m = (next - current).cwiseAbs().maxCoeff();
    current.swap(next);
    if (r.iterations <= 6) tau_s = std::min(kLongestTau_s, 2.0 * tau_s);
    // Nearly at rest, or steps so long that inertia hardly matters: try to finish with Newton.
    if (--steps_until_polish <= 0 && (largest_move_m < 1e-3 || tau_s >= 1.0)) {
      VecX polished = current;
      const SolveReport p = newton_.minimize(objective_, dofs, force_scale_N, polished, polish_options);
      account(p);
      if (p.usable()) {
        report.status = p.status;
        report.message = p.message;
        current.swap(polished);
        break;
      }
      steps_until_polish = 4;
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report.usable()) x.swap(current);
  return report;
}

}  // namespace twin

namespace twin {

SolveReport StaticSolver::solve_from_equilibrium(const ClampSet& clamps,
                                                 const std::vector<ClampPose>& poses, VecX& x,
                                                 const NewtonOptions& options) {
  const DofMap dofs = model_.hold_clamps(clamps, poses);
  VecX moved = x;
  clamps.hold(poses, moved);
  // With slipping clamps no vertex is held, but the prediction holds the clamps' vertices at
  // their new poses as rigid jaws would: a hanging sheet has several equilibria, and the path
  // is then the rigid clamps' one up to the slip, which the Newton solve below adds. (Newton's
  // own first step from the old equilibrium, pulled by the slip springs, is a prediction too,
  // but capped and line-searched: it took other branches, moving markers by up to 20 mm in
  // the lab's trials at zero compliance.)
  VecX trial = model_.clamp_slip().has_clamps()
                   ? held_predictor_.tangent_predictor(
                         objective_, DofMap(clamps.fixed_vertices(model_.vertex_count(), poses)), x, moved)
                   : newton_.tangent_predictor(objective_, dofs, x, moved);
  SolveReport report = newton_.minimize(objective_, dofs, free_weight_N(model_, dofs), trial, options);
  if (!report.usable()) {
    // The prediction can overshoot where the response is strongly nonlinear (a fold snapping
    // through); the plain start is slower but safe.
    trial = moved;
    report.append(newton_.minimize(objective_, dofs, free_weight_N(model_, dofs), trial, options));
  }
  if (report.usable()) x.swap(trial);
  return report;
}

}  // namespace twin
