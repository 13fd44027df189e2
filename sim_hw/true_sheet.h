#pragma once
// The fake world's true sheet: the truth material in the independent plate model (or, by
// config, the twin's own shell model; true_sheet_physics.h), advanced in real time by
// linearised backward Euler, held by whichever grippers are closed on it. A gripper that closes grips the sheet's material point nearest its jaw (within a
// capture distance) as that patch lies at that moment, and then carries the patch rigidly with
// the jaw (position and turn); a gripper that opens lets go and the sheet swings under its own
// physics.
//
// Threads: step() belongs to one thread (the physics thread); grip / release / move_jaw and the
// read accessors may be called from any thread (a mutex guards the grips and the published
// state). A step that fails leaves the state as it was (the stepper's own sub-step retries come
// first) and is counted. The twin has no contact model: with no gripper holding, the sheet would
// fall for ever, so the physics pauses until something grips it again (it "lies on the floor").

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim_hw/true_sheet_physics.h"
#include "twin/model/clamp.h"
#include "twin/trials/sheet_spec.h"
#include "twin/solvers/solve_report.h"

namespace sim_hw {

// A grasp the sheet starts in (the initial load): the clamp (id = gripper), where its patch is
// held (position and turn; columns = world directions of material u, v, normal) and the jaw's
// pose then (position = jaw centre, rotation = flange rotation), in the cell frame (m).
struct HeldGrasp {
  twin::ClampSpec clamp;
  Eigen::Isometry3d patch_pose = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d jaw_pose = Eigen::Isometry3d::Identity();
};

struct StepStats {
  std::uint64_t steps = 0, failures = 0;
  double last_step_ms = 0, max_step_ms = 0;
  int last_substeps = 0;
  bool paused = false;  // nothing holds the sheet
  std::string last_failure;
};

class TrueSheet {
 public:
  // Throws std::invalid_argument for an invalid mesh or material, or a sheet the model cannot
  // take (true_sheet_physics.h).
  TrueSheet(const twin::SheetSpec& sheet, const twin::Material& material, const TrueSheetOptions& options = {});

  // Places the flat sheet, holds the grasps' patches at their held poses and solves the static
  // equilibrium (twin StaticSolver, settling when Newton alone stalls), so the sheet starts at
  // rest hanging as loaded. Throws std::runtime_error saying why if it does not converge or a
  // clamp is invalid (naming the gripper).
  twin::SolveReport load(const std::vector<HeldGrasp>& grasps);

  // Closes gripper `name` with its jaw at `jaw_pose`: grips the nearest vertex's material point
  // if it is within capture_m of the jaw centre (grip radius radius_m). Returns whether it holds.
  bool grip(const std::string& name, const Eigen::Isometry3d& jaw_pose, double capture_m, double radius_m);
  void release(const std::string& name);
  // The jaw of a holding gripper moved (ignored when `name` holds nothing).
  void move_jaw(const std::string& name, const Eigen::Isometry3d& jaw_pose);
  bool holding(const std::string& name) const;
  int holding_count() const;

  // One real-time step of dt_s (physics thread).
  void step(double dt_s);

  const twin::SheetMesh& mesh() const { return physics_->mesh(); }
  twin::VecX positions() const;  // the latest state (3n, m)
  std::uint64_t version() const; // increments with every state change
  StepStats stats() const;
  // Lowest vertex below the mean height of the holding patches (m); 0 when nothing holds.
  double sag_m() const;

 private:
  struct Grip {
    twin::ClampSpec clamp;
    Eigen::Isometry3d patch_in_jaw = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d jaw_pose = Eigen::Isometry3d::Identity();
  };
  std::vector<twin::ClampSpec> specs_locked() const;
  std::vector<twin::ClampPose> poses_locked() const;

  std::unique_ptr<TrueSheetPhysics> physics_;
  twin::SheetPlacement placement_;
  twin::VecX x_, v_;  // physics thread's state

  mutable std::mutex mutex_;  // guards everything below
  std::map<std::string, Grip> grips_;
  bool grips_changed_ = true;
  twin::VecX published_x_;
  std::uint64_t version_ = 0;
  StepStats stats_;
};

}  // namespace sim_hw
