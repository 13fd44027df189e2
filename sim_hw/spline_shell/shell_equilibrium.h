#pragma once
// Static equilibrium of the reference sheet: the shell (shell_model.h) with some control points
// held where they are put: the square jaws' (square_jaw.h, placed at each jaw's pose; wide and
// slipping jaws add grip springs, jaw_grip.h, and slipping ones leave the pad's controls free)
// and any other fixed controls (a clamped edge's first two rows hold its position and slope). The free
// controls are found by the lab's damped Newton method (sim_hw/real_sheet/damped_newton.h) on
// CHOLMOD, with the controls' masses as its metric; the held ones are fixed unknowns (identity
// rows), exact at every refinement, with no penalty to tune (the grip springs are physics: the
// lab's hidden effects, not a way of holding).

#include <vector>

#include <Eigen/Core>

#include "sim_hw/real_sheet/damped_newton.h"
#include "sim_hw/spline_shell/shell_model.h"
#include "sim_hw/spline_shell/square_jaw.h"

namespace sim_hw::spline_shell {

struct JawHold {
  SquareJaw jaw;
  Vec3 centre_m = Vec3::Zero();  // where the jaw holds the clamp's material point
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // columns: world u, v, normal of the pad
};

struct ShellHolds {
  std::vector<JawHold> jaws;
  std::vector<int> fixed_controls;  // held where x has them
};

struct ShellSolveOptions {
  double force_tolerance = 1e-9;  // of the sheet's weight, per free control
  double step_tolerance_m = 1e-10;
  int max_iterations = 400;
  double initial_damping_1_s2 = 0.0;
  double step_limit_m = 0.05;
  // Relax first by preconditioned L-BFGS (preconditioned_lbfgs.h) down to this fraction of the
  // sheet's weight per free control, Newton's method after: for a state near its equilibrium
  // (a shape carried to a finer patch) most iterations then need no factorisation. 0: Newton
  // from the start. Only without initial damping (a fall stays an overdamped motion).
  double relax_to_force = 0;
  bool trace = false;  // also SPLINE_SHELL_TRACE in the environment
};

struct ShellSolveReport : real_sheet::DampedNewtonReport {
  int relaxation_iterations = 0;  // preconditioned L-BFGS's, before Newton's `iterations`
};

// Every control the holds fix (sorted, distinct): the fixed ones and, unless the jaws slip, the
// pads'.
std::vector<int> fixed_controls(const ShellModel& model, const ShellHolds& holds);
// Places every jaw's pad controls at its pose in x (for slipping jaws a predictor, for the rest
// their hold) and returns fixed_controls.
std::vector<int> apply_holds(const ShellModel& model, const ShellHolds& holds, VecX& x);

// Puts the jaws' controls at their poses and solves for the rest; x (control points, m) is
// updated in place on success and left as it was on failure.
ShellSolveReport solve_shell(const ShellModel& model, const ShellHolds& holds, VecX& x,
                             const ShellSolveOptions& options = {});

// How stable an equilibrium is: the lowest eigenvalue lambda (1/s^2) of H v = lambda M v over
// the free controls (H the exact Hessian, M the controls' masses): the square of the sheet's
// lowest natural angular frequency about x, found by inverse iteration on H's Cholesky factor.
// NaN when H is not positive definite there (x is no stable equilibrium). A branch that is about
// to fold shows as lambda falling towards zero.
double lowest_eigenvalue_1_s2(const ShellModel& model, const ShellHolds& holds, const VecX& x, int iterations = 60);

// The jaws' grip springs beyond their fixed controls (wide and slipping jaws, jaw_grip.h) at
// the holds' poses: energy (J); adds the gradient and Hessian when non-null.
double holds_energy(const ShellModel& model, const ShellHolds& holds, const VecX& x, VecX* gradient,
                    BlockSparseMatrix* hessian);

// The force (N) the holds exert on the sheet at an equilibrium x (z up: the sheet's weight when
// they carry it): the fixed controls' reactions plus the grip springs' pull on the free controls.
Vec3 holding_force_N(const ShellModel& model, const ShellHolds& holds, const VecX& x);

}  // namespace sim_hw::spline_shell
