#include "twin/solvers/implicit_stepper.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "twin/solvers/static_solver.h"

namespace twin {

StepOptions default_step_options() {
  StepOptions options;
  options.newton.max_iterations = 20;
  // Force imbalance below 1e-5 of the sheet's weight: far below what a camera can see.
  options.newton.residual_tolerance = 1e-5;
  // The exact Hessian near the solution gives quadratic convergence; the projected one alone
  // converges only linearly wherever the membrane is in compression (measured: 16 vs 4-6
  // iterations per step on the benchmark sheet).
  options.newton.exact_hessian_below = 0.1;
  // The incremental potential is well scaled by inertia: no need to look past a full step.
  options.newton.max_extrapolation = 1.0;
  // Successive time steps have similar Hessians: reuse the factorisation as a CG
  // preconditioner (measured 8 % faster per step on the benchmark sheet, 4x fewer factorisations).
  options.newton.linear.reuse_factorization = true;
  return options;
}

StepOptions linearized_step_options() {
  StepOptions options = default_step_options();
  options.newton.max_iterations = 1;
  options.newton.accept_iteration_budget = true;
  options.newton.exact_hessian_below = 0.0;  // one step: the projected Hessian is the safe one
  return options;
}

StepOptions background_linearized_step_options() {
  StepOptions options = linearized_step_options();
  // One linear solve per step. While the sheet moves, each step hands the next step's Hessian
  // (predicted: see prefactorize_next_step) to be factorised on the other core, and is itself
  // solved by CG preconditioned with the factor its predecessor handed over
  // (newton_linear_solver.h), to 0.01 mm per vertex.
  options.newton.linear.background_factorization = true;
  options.newton.linear.cg_vertex_error_m = 1e-5;
  return options;
}

ImplicitStepper::ImplicitStepper(const ShellModel& model)
    : model_(model),
      inertia_(model.vertex_masses_kg(), model.material().mass_damping_1_s),
      viscosity_(model.membrane().elements(), model.vertex_count(),
                 model.material().tensile_viscosity_Ns_m, model.material().shear_viscosity_Ns_m) {}

void ImplicitStepper::sync_material() {
  inertia_.set_masses(model_.vertex_masses_kg());
  inertia_.set_mass_damping(model_.material().mass_damping_1_s);
  viscosity_.set_viscosity(model_.material().tensile_viscosity_Ns_m,
                           model_.material().shear_viscosity_Ns_m);
  newton_.invalidate_factorization();
}

SolveReport ImplicitStepper::step(VecX& x, VecX& v, double dt_s, const ClampSet& clamps,
                                  const std::vector<ClampPose>& poses,
                                  const StepOptions& options) {
  // Sub-steps move each clamp from where it was to `poses`. A clamp that was not holding (or
  // the first call) starts from where its material point is now, with the target orientation.
  std::vector<ClampPose> start = previous_poses_;
  start.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (i >= previous_poses_.size() || !previous_poses_[i].engaged) {
      start[i].position_m = clamps[static_cast<int>(i)].material_point_position(x);
      start[i].rotation = clamps[static_cast<int>(i)].material_frame(x);
      start[i].engaged = true;
    }
  }
  SolveReport total;
  for (int substeps = 1; substeps <= std::max(1, options.max_substeps); substeps *= 2) {
    VecX xs = x, vs = v;
    SolveReport report;
    for (int k = 1; k <= substeps; ++k) {
      std::vector<ClampPose> at(poses.size());
      for (std::size_t i = 0; i < poses.size(); ++i) {
        at[i] = interpolate(start[i], poses[i], static_cast<double>(k) / substeps);
      }
      report = single_step(xs, vs, dt_s / substeps, clamps, at, options);
      total.iterations += report.iterations;
      total.factorizations += report.factorizations;
      total.cg_iterations += report.cg_iterations;
      total.fallbacks += report.fallbacks;
      total.factor_wait_s += report.factor_wait_s;
      total.seconds += report.seconds;
      if (!report.usable()) break;
    }
    total.status = report.status;
    total.residual = report.residual;
    total.energy_J = report.energy_J;
    total.message = report.message;
    last_substeps_ = substeps;
    if (report.usable()) {
      x.swap(xs);
      v.swap(vs);
      previous_poses_ = poses;
      const NewtonOptions& newton = options.newton;
      if (newton.linear.reuse_factorization && newton.linear.background_factorization) {
        // The factor at hand still did (no CG iteration) and the clamps stood: no new one.
        double clamp_move_m = 0.0;
        for (std::size_t i = 0; i < poses.size(); ++i) {
          clamp_move_m = std::max(clamp_move_m, (poses[i].position_m - start[i].position_m).norm());
        }
        if (total.cg_iterations > 0 || total.fallbacks > 0 || total.factorizations > 0 ||
            clamp_move_m > options.refactorize_above_clamp_move_m) {
          prefactorize_next_step(x, v, dt_s, clamps, start, poses);
        }
      }
      return total;
    }
  }
  return total;
}

SolveReport ImplicitStepper::single_step(VecX& x, VecX& v, double dt_s, const ClampSet& clamps,
                                         const std::vector<ClampPose>& poses,
                                         const StepOptions& options) {
  const DofMap dofs = model_.hold_clamps(clamps, poses);
  inertia_.set_step(x, v, dt_s);
  viscosity_.set_step(x, dt_s);
  // Start from the inertial prediction; clamped vertices go to their poses (slipping clamps'
  // vertices are free and carry their slip along in the prediction).
  VecX next = x + dt_s * v;
  if (!model_.clamp_slip().has_clamps()) clamps.hold(poses, next);
  SolveReport report =
      newton_.minimize(Objective(step_terms()), dofs, free_weight_N(model_, dofs), next, options.newton);
  if (!report.usable()) return report;
  VecX velocity = (next - x) / dt_s;
  double top_speed = 0.0;
  for (int i = 0; i < dofs.vertex_count(); ++i) top_speed = std::max(top_speed, velocity.segment<3>(3 * i).norm());
  if (!(top_speed <= options.max_speed_m_s)) {
    report.status = SolveStatus::kBlowUp;
    report.message = fmt::format("speed {:.3g} m/s > {:.3g} m/s", top_speed, options.max_speed_m_s);
    return report;
  }
  x.swap(next);
  v.swap(velocity);
  return report;
}

std::vector<const EnergyTerm*> ImplicitStepper::step_terms() const {
  // Viscosity joins only when the material has some: its element loop is not free.
  std::vector<const EnergyTerm*> terms = model_.potential_terms();
  terms.push_back(&inertia_);
  if (viscosity_.active()) terms.push_back(&viscosity_);
  return terms;
}

void ImplicitStepper::prefactorize_next_step(const VecX& x, const VecX& v, double dt_s,
                                             const ClampSet& clamps, const std::vector<ClampPose>& from,
                                             const std::vector<ClampPose>& to) {
  // The next step starts from its inertial prediction x + dt v, which is known now; only the
  // clamps' next poses are guessed, as going on at the speed they had in this step. (Predicting
  // two steps ahead, to give the factorisation two steps' time, does not pay: on the 6k
  // benchmark sheet its factor needed 6.8 CG iterations per step, as a factor a step old does.)
  std::vector<ClampPose> poses = to;
  for (std::size_t i = 0; i < to.size(); ++i) {
    poses[i].position_m = to[i].position_m + (to[i].position_m - from[i].position_m);
  }
  const DofMap dofs = model_.hold_clamps(clamps, poses);
  inertia_.set_step(x, v, dt_s);
  viscosity_.set_step(x, dt_s);
  VecX start = x + dt_s * v;
  if (!model_.clamp_slip().has_clamps()) clamps.hold(poses, start);
  newton_.prefactorize(Objective(step_terms()), dofs, start);
  ++background_factorizations_;
}

double kinetic_energy(const ShellModel& model, const VecX& v) {
  double energy = 0.0;
  for (int i = 0; i < model.vertex_count(); ++i) {
    energy += 0.5 * model.vertex_masses_kg()[i] * v.segment<3>(3 * i).squaredNorm();
  }
  return energy;
}

}  // namespace twin
