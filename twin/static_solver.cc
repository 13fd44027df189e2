#include "twin/static_solver.h"

#include <cmath>

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
    : model_(model), objective_(model.potential_terms()) {}

double free_weight_N(const ShellModel& model, const DofMap& dofs) {
  double sum = 0.0;
  const double g = model.gravity().gravity().norm();
  for (int v = 0; v < dofs.vertex_count(); ++v) {
    if (!dofs.is_fixed(v)) sum += std::pow(model.vertex_masses_kg()[v] * g, 2);
  }
  return std::sqrt(sum);
}

SolveReport StaticSolver::solve(const ClampSet& clamps, const std::vector<ClampPose>& poses,
                                VecX& x, const NewtonOptions& options) {
  const DofMap dofs(clamps.fixed_vertices(model_.vertex_count(), poses));
  VecX trial = x;
  clamps.hold(poses, trial);
  SolveReport report = newton_.minimize(objective_, dofs, free_weight_N(model_, dofs), trial, options);
  if (report.usable()) x.swap(trial);
  return report;
}

}  // namespace twin

namespace twin {

SolveReport StaticSolver::solve_from_equilibrium(const ClampSet& clamps,
                                                 const std::vector<ClampPose>& poses, VecX& x,
                                                 const NewtonOptions& options) {
  const DofMap dofs(clamps.fixed_vertices(model_.vertex_count(), poses));
  VecX moved = x;
  clamps.hold(poses, moved);
  VecX trial = newton_.tangent_predictor(objective_, dofs, x, moved);
  SolveReport report = newton_.minimize(objective_, dofs, free_weight_N(model_, dofs), trial, options);
  if (!report.usable()) {
    // The prediction can overshoot where the response is strongly nonlinear (a fold snapping
    // through); the plain start is slower but safe.
    trial = moved;
    const SolveReport plain = newton_.minimize(objective_, dofs, free_weight_N(model_, dofs), trial, options);
    report.iterations += plain.iterations;
    report.factorizations += plain.factorizations;
    report.seconds += plain.seconds;
    report.status = plain.status;
    report.residual = plain.residual;
    report.energy_J = plain.energy_J;
    report.message = plain.message;
  }
  if (report.usable()) x.swap(trial);
  return report;
}

}  // namespace twin
