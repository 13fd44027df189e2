#pragma once
// The scanner lab's handling of the reference sheet through a trial's stages, as the lab's
// plate is handled (sim_hw/real_sheet/stage_path.h, the same protocol): the sheet lies flat and
// level (placed so its clamps' material points best fit their stage-1 positions); the jaws close
// on it there and it is let go into gravity (an overdamped fall: the damped Newton method's
// pseudo-time); the jaws then travel to each stage's poses in increments, each solved to
// equilibrium from a secant predictor; a jaw that opens lets the sheet fall again; a jaw that
// closes later takes the sheet as it hangs, in the sheet's own frame there. With creep, moves
// are made on the fresh material and the stage is then solved again at its age.
// The path is followed on one patch; carry_to_patch puts a stage onto a finer one (exact knot
// insertion, then re-equilibrated), so a refinement study compares levels on one branch.

#include <string>
#include <vector>

#include "sim_hw/real_sheet/stage_path.h"  // PathStage, level_placement
#include "sim_hw/spline_shell/shell_equilibrium.h"
#include "twin/model/clamp.h"

namespace sim_hw::spline_shell {

struct ShellPathOptions {
  double increment_m = 0.02;  // largest jaw travel per solved increment
  ShellSolveOptions solve;    // per increment
  double fall_damping_1_s2 = 1e4;
  // carry_path: a stage where a jaw opens or closes falls again on the finer patch from the
  // stage before it there (true), or is carried from the coarser patch's fallen shape like any
  // other stage (false: every level on the coarsest level's branch, what a refinement study
  // compares; a fall's end is a branch choice of the overdamped motion, not a discretisation).
  bool replay_falls = false;
  // carry_to_patch: relax the carried shape by preconditioned L-BFGS to this fraction of the
  // weight per control before Newton's method (ShellSolveOptions::relax_to_force; 0: Newton only).
  double carry_relax_to_force = 1e-6;
};

struct ShellPathResult {
  std::vector<VecX> stages;        // equilibrium controls per stage reached
  std::vector<ShellHolds> holds;   // per stage, the jaws holding and their poses
  std::vector<ShellSolveReport> reports;
  int increments = 0, iterations = 0, factorizations = 0;
  std::string failure;  // "stage 3: ..." when a stage was not reached
  bool usable() const { return failure.empty(); }
};

// The clamps' square jaws (clamp order). Throws std::invalid_argument as square_jaw does.
std::vector<SquareJaw> clamp_jaws(const std::vector<twin::ClampSpec>& clamps, double width_m, double height_m);

ShellPathResult follow_path(ShellModel& model, const std::vector<SquareJaw>& jaws,
                            const std::vector<real_sheet::PathStage>& stages, const ShellPathOptions& options = {});

// Whether the stage opens a jaw that held the sheet before it, or closes one that did not: the
// sheet falls there (an overdamped motion whose end depends on the model, not a nearby
// equilibrium to re-solve).
bool lets_go(const ShellHolds& before, const real_sheet::PathStage& stage, const std::vector<SquareJaw>& jaws);

// One stage of the protocol from an equilibrium x held by `holds` (the stage before it, on this
// model): what follow_path does there, fall included. The stage's holds go to holds_after;
// iterations and factorisations in report are the stage's whole. Throws std::runtime_error when
// the stage is not reached, std::invalid_argument as follow_path.
VecX replay_stage(ShellModel& model, const std::vector<SquareJaw>& jaws, const VecX& x, const ShellHolds& holds,
                  const real_sheet::PathStage& stage, ShellHolds* holds_after = nullptr,
                  const ShellPathOptions& options = {}, ShellSolveReport* report = nullptr);

// A stage's equilibrium x on `from` carried onto `to` (whose knots refine from's) and solved
// there with the same holds. `to` must be at the stage's age. Throws std::runtime_error when the
// solve does not converge.
VecX carry_to_patch(const ShellModel& from, const VecX& x, const ShellHolds& holds, const ShellModel& to,
                    const ShellPathOptions& options = {}, ShellSolveReport* report = nullptr);

// A path's stages (x, holds: follow_path's or a coarser carry's) put onto a finer patch, in
// order: each is carried exactly (carry_to_patch), its jaws keeping the frames they took on `to`;
// with options.replay_falls, a stage where a jaw opens or closes (lets_go) falls again on `to`
// from the stage before it there (replay_stage) instead. Repeated scans of one pose stay one
// state. Stage ages come from `stages` (with creep). Throws std::runtime_error naming the stage
// that did not settle.
struct CarriedPath {
  std::vector<VecX> stages;
  std::vector<ShellHolds> holds;
  std::vector<int> replayed;  // stages (0-based) that fell again on the finer patch
  int iterations = 0;             // Newton's
  int relaxation_iterations = 0;  // preconditioned L-BFGS's
};
CarriedPath carry_path(ShellModel& from, const std::vector<VecX>& x, const std::vector<ShellHolds>& holds, ShellModel& to,
                       const std::vector<SquareJaw>& jaws, const std::vector<real_sheet::PathStage>& stages,
                       const ShellPathOptions& options = {});

// The age a stage's equilibrium is solved at: its own with creep, 0 (fresh) without.
double stage_age_s(const ShellModel& model, const real_sheet::PathStage& stage);

}  // namespace sim_hw::spline_shell
