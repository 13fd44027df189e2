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
