#pragma once
// The cell's digital twin of the held ply: the sheet mesh and material, one clamp per grasp of
// the plan, a static equilibrium at start-up (and after a failure) and one linearised
// backward-Euler step per cycle with the clamps at the measured grasp positions. Failures come
// back as values (the cycle must not throw); a failed or non-finite step leaves the state as it
// was and the caller publishes nothing from it.
#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "twin/model/clamp.h"
#include "twin/trials/grasp_plan.h"
#include "twin/solvers/implicit_stepper.h"
#include "twin/model/material.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace cell {

struct TwinStepResult {
  bool ok = false;
  std::string message;  // why not ok
  double step_ms = 0;
  int substeps = 0;     // > 1: the step was retried in shorter sub-steps (see implicit_stepper.h)
  int iterations = 0;   // Newton iterations over all sub-steps
};

class CellTwin {
 public:
  // placement: where the flat sheet starts before the first static solve. Throws
  // std::invalid_argument when the plan's grasps are not on the sheet.
  CellTwin(const twin::SheetMesh& mesh, const twin::Material& material, const twin::GraspPlan& plan,
           const twin::SheetPlacement& placement);

  // Static equilibrium with grasp i held at grasp_positions_m[i] (released grasps ignored),
  // from the flat placement the first time and from the last state afterwards. "" or why not.
  std::string initialise(const std::vector<twin::Vec3>& grasp_positions_m);
  // Hot swap (in-situ calibration): the twin runs `material` from now on, and its state becomes
  // the static equilibrium under it with grasp i held at grasp_positions_m[i], from the current
  // state (a new material moves the sheet; carrying the old velocity would not be its motion).
  // "" or why not; on failure the twin keeps its old material and state.
  std::string set_material(const twin::Material& material, const std::vector<twin::Vec3>& grasp_positions_m);
  const twin::Material& material() const { return model_->material(); }

  // Branch following (cell/learning/branch_following.h): the twin continues from `x` (3n, m),
  // an equilibrium found near the settled sheet the cameras saw, at rest.
  void adopt_state(const twin::VecX& x);
  // How the clamps hold their patches (turned as the ply lay flat; fixed at construction).
  const twin::Mat3& jaw_rotation() const { return jaw_rotation_; }

  // One dynamic step of dt_s with the clamps moved to grasp_positions_m.
  TwinStepResult step(double dt_s, const std::vector<twin::Vec3>& grasp_positions_m);

  // cell.twin_background_factorization: steps with twin::background_linearized_step_options
  // (the default) or twin::linearized_step_options. Not while a step runs.
  void set_background_factorization(bool on);

  // The clamp of grasp i lets go (the gripper opened); it does not grip again.
  void release(int grasp);
  bool engaged(int grasp) const { return poses_[grasp].engaged; }
  // Fault injection (fake hardware only): while set, every step is fed non-finite clamp
  // positions, so it fails the way a diverging solve does.
  // (Set from the bus handler while a step may run on the twin's worker: atomic.)
  void set_poisoned(bool poisoned) { poisoned_ = poisoned; }
  bool poisoned() const { return poisoned_; }
  // Fault injection (fake hardware only): each step takes this much longer, as a twin that
  // cannot keep up with the cycle would (atomic for the same reason).
  void set_stall(std::chrono::milliseconds stall) { stall_ms_ = static_cast<int>(stall.count()); }

  bool initialised() const { return initialised_; }
  const twin::VecX& positions() const { return x_; }
  const twin::SheetMesh& mesh() const { return model_->mesh(); }
  int grasp_count() const { return clamps_.size(); }

 private:
  void set_positions(const std::vector<twin::Vec3>& grasp_positions_m);

  std::unique_ptr<twin::ShellModel> model_;
  twin::ClampSet clamps_;
  std::vector<twin::ClampPose> poses_;
  twin::VecX x_, v_;
  std::unique_ptr<twin::StaticSolver> statics_;
  std::unique_ptr<twin::ImplicitStepper> stepper_;
  twin::StepOptions step_options_;
  twin::Mat3 jaw_rotation_ = twin::Mat3::Identity();
  bool initialised_ = false;
  std::atomic<bool> poisoned_{false};
  std::atomic<int> stall_ms_{0};
};

// The flat start when the config gives no placement: unrotated (u along x, v along y), the
// grasps' material points centred over their hold positions, at their mean height.
twin::SheetPlacement placement_under_grasps(const twin::GraspPlan& plan);

}  // namespace cell
