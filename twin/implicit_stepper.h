#pragma once
// One backward-Euler step of the sheet's dynamics, solved as the minimisation of the
// incremental potential (inertia + damping + viscosity + elastic + gravity; see inertia_term.h
// and viscosity_term.h) by Newton. Clamps are at their poses for the end of the step.
// Unconditionally stable for any dt; it dissipates energy (numerically, on top of the
// material's viscosity), which is right for a sheet settling in air.

#include "twin/clamp.h"
#include "twin/inertia_term.h"
#include "twin/newton_solver.h"
#include "twin/shell_model.h"
#include "twin/viscosity_term.h"

namespace twin {

struct StepOptions {
  NewtonOptions newton;
  // A step whose velocities exceed this is rejected as a blow-up (m/s).
  double max_speed_m_s = 50.0;
};

StepOptions default_step_options();

class ImplicitStepper {
 public:
  explicit ImplicitStepper(const ShellModel& model);

  // Advances positions x and velocities v (3n, m and m/s) by dt (s). On failure both are
  // unchanged and the report says why.
  SolveReport step(VecX& x, VecX& v, double dt_s, const ClampSet& clamps,
                   const std::vector<ClampPose>& poses,
                   const StepOptions& options = default_step_options());

  // Picks up a material change made on the model (viscosity, mass damping, density).
  void sync_material();

 private:
  const ShellModel& model_;
  InertiaTerm inertia_;
  ViscosityTerm viscosity_;
  Objective objective_;
  NewtonSolver newton_;
};

// Kinetic energy (J) of velocities v with the model's lumped masses.
double kinetic_energy(const ShellModel& model, const VecX& v);

}  // namespace twin
