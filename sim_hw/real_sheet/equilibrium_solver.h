#pragma once
// Minimises the independent sheet's potential: static equilibrium (or one implicit step) by a
// damped Newton method. Each iteration solves (H + mu M) dx = -g, with M the lumped masses, and
// backtracks along dx until the energy falls. mu (1/s^2) is a pseudo-time damping: large, the
// step is a short overdamped motion under the forces (how a released or folding sheet really
// moves, and what picks its branch); zero, it is Newton's step. mu shrinks after full steps and
// grows after failed ones. H is the exact Hessian when mu is zero and it is positive definite,
// the projected one (tension-field membrane, Gauss-Newton bending) otherwise.
// Converged when every node's force and every pivot's moment are below the tolerance, or a
// Newton step moves nothing any more. On
// failure the positions and jaw turns are left as they were.

#include <string>
#include <vector>

#include <memory>

#include "sim_hw/real_sheet/cholesky.h"
#include "sim_hw/real_sheet/sheet_model.h"

namespace sim_hw::real_sheet {

struct EquilibriumOptions {
  // Converged when |force| on each node is below this share of the sheet's weight (N per N).
  double force_tolerance = 1e-9;
  // ... or when a Newton step moves no node by more than this (m): stiff jaw pads leave forces
  // of rounding size (pad stiffness x 1e-16 m) that no step can lower.
  double step_tolerance_m = 1e-10;
  int max_iterations = 400;
  double initial_damping_1_s2 = 0.0;  // mu to start with (0: plain Newton first)
  // A real-time step's budget: at the iteration limit keep the last accepted iterate (its energy
  // is below the start's) instead of failing; the report says "iteration budget used".
  bool keep_on_limit = false;
  // Projected Hessian only (no exact attempt): for implicit steps, whose inertia makes it
  // positive definite and a good model, at half the factorisations.
  bool projected_hessian = false;
  // The first trust radius (m): no node moves further in one step until steps prove good. An
  // implicit step's Newton step is the scheme's own and is not cut: give it a large radius.
  double step_limit_m = 0.05;
};

struct EquilibriumReport {
  bool converged = false;
  bool budget_used = false;  // keep_on_limit: stopped at the limit, the state kept
  int iterations = 0, factorizations = 0;
  double max_force_N = 0;
  double energy_J = 0;
  std::string message;  // why it stopped when not converged
};

// The Hessian's pattern and its Cholesky analysis, kept between solves with the same jaws (a
// real-time stepper's every step): rebuilding them costs more than a step's factorisation.
class SolveWorkspace {
 public:
  SolveWorkspace();
  ~SolveWorkspace();
  // The pattern for these jaws, rebuilt only when their pads' nodes or kinds changed.
  BlockSparseMatrix& pattern(const SheetModel& model, const std::vector<JawHold>& jaws);
  Cholesky& cholesky() { return *cholesky_; }

 private:
  std::vector<std::vector<int>> key_;
  BlockSparseMatrix pattern_;
  std::unique_ptr<Cholesky> cholesky_;
  bool built_ = false;
};

// x (3 n, m) and the pivot jaws' rotations are updated in place on success.
EquilibriumReport solve_equilibrium(const SheetModel& model, VecX& x, std::vector<JawHold>& jaws,
                                    const EquilibriumOptions& options = {}, const StepTerms* step = nullptr,
                                    SolveWorkspace* workspace = nullptr);

}  // namespace sim_hw::real_sheet
