#pragma once
// One backward-Euler step of the sheet's dynamics, solved as the minimisation of the
// incremental potential (inertia + damping + viscosity + elastic + gravity; see inertia_term.h
// and viscosity_term.h) by Newton. Clamps are at their poses for the end of the step.
// Unconditionally stable for any dt; it dissipates energy (numerically, on top of the
// material's viscosity), which is right for a sheet settling in air.

#include "twin/model/clamp.h"
#include "twin/model/inertia_term.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/shell_model.h"
#include "twin/model/viscosity_term.h"

namespace twin {

struct StepOptions {
  NewtonOptions newton;
  // A step whose velocities exceed this is rejected as a blow-up (m/s).
  double max_speed_m_s = 50.0;
  // A step that does not converge is retried as 2, 4, ... sub-steps, up to this many. A sheet
  // in compression can buckle within one step; shorter steps add inertia (m/dt^2) to the
  // Hessian and make each sub-step well posed again.
  int max_substeps = 8;
  // Background factorisation (linearized_step_options): a step after which the clamps moved
  // less than this (m) and whose CG needed no iteration hands over no new Hessian; the sheet is
  // at rest and the factor at hand still fits.
  double refactorize_above_clamp_move_m = 1e-4;
};

// Backward Euler solved to convergence (residual 1e-5 of the weight) in every step.
StepOptions default_step_options();
// Linearised backward Euler: one Newton iteration per step (Baraff and Witkin 1998; what
// VegaFEM's implicit integrator does by default, the paper's engine). The step is accepted when
// it lowered the incremental potential with finite forces and speeds; it is first-order
// accurate like the converged step but not its exact solution.
StepOptions linearized_step_options();
// The same with background factorisation (newton_linear_solver.h): while the sheet moves, the
// next step's Hessian, predicted from the step just taken, is factorised on a worker thread,
// and each step is solved by CG with the factor its predecessor predicted, to 0.01 mm per
// vertex. It trades a factorisation on the critical path for a second Hessian assembly; the
// result does not depend on timing.
StepOptions background_linearized_step_options();

class ImplicitStepper {
 public:
  explicit ImplicitStepper(const ShellModel& model);

  // Advances positions x and velocities v (3n, m and m/s) by dt (s), the clamps moving from
  // their poses of the previous call to `poses`; a clamp that was not holding (or on the first
  // call) moves from where and how its material point is in x. On failure x
  // and v are unchanged and the report says why. The report's iterations and factorizations
  // add up over sub-steps; `substeps` says how many were needed.
  SolveReport step(VecX& x, VecX& v, double dt_s, const ClampSet& clamps,
                   const std::vector<ClampPose>& poses,
                   const StepOptions& options = default_step_options());
  int last_substeps() const { return last_substeps_; }
  // Background factorisation: predicted Hessians handed to the worker so far.
  int background_factorizations() const { return background_factorizations_; }

  // Picks up a material change made on the model (viscosity, mass damping, density).
  void sync_material();

 private:
  SolveReport single_step(VecX& x, VecX& v, double dt_s, const ClampSet& clamps,
                          const std::vector<ClampPose>& poses, const StepOptions& options);
  std::vector<const EnergyTerm*> step_terms() const;
  // Background factorisation: hands the next step's Hessian, predicted with the clamps going on
  // from `from` through `to` at the same speed, to the factorisation worker.
  void prefactorize_next_step(const VecX& x, const VecX& v, double dt_s, const ClampSet& clamps,
                              const std::vector<ClampPose>& from, const std::vector<ClampPose>& to);

  const ShellModel& model_;
  std::vector<ClampPose> previous_poses_;
  int last_substeps_ = 0;
  int background_factorizations_ = 0;
  InertiaTerm inertia_;
  ViscosityTerm viscosity_;
  NewtonSolver newton_;
};

// Kinetic energy (J) of velocities v with the model's lumped masses.
double kinetic_energy(const ShellModel& model, const VecX& v);

}  // namespace twin
