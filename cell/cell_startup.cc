// CellController's start-up sequence: cameras (open, first frames) -> material and grasp plan
// -> robots (a status from every arm, each holding gripper where the plan says) -> twin (static
// equilibrium at the measured grasps) -> first tracked frame and calibration check -> READY.
// Each step that fails ends in FAILED with a reason precise enough to act on.
#include <fmt/format.h>

#include <algorithm>

#include "cell/cell_controller.h"
#include "cell/sheet_compare.h"
#include "drivers/lcm_channels.h"
#include "twin/model/material.h"

namespace cell {

CellState CellController::fail(const std::string& why) {
  status_.state = CellState::kFailed;
  status_.reason = why;
  publish_state();
  return status_.state;
}

std::string CellController::open_cameras(double deadline_s) {
  if (std::string why = cameras_.open(config_.cameras); !why.empty()) return why;
  // Every camera must deliver a usable frame: a cell should not start with a camera missing.
  const double camera_deadline = std::min(deadline_s, steady_s() + config_.cell.camera_startup_timeout_s);
  std::vector<bool> seen(cameras_.size(), false);
  for (;;) {
    std::vector<drivers::DepthFrame> frames;
    cameras_.read_all(frames);
    wait_for_next_frames();
    for (int i = 0; i < cameras_.size(); ++i) seen[i] = seen[i] || cameras_.slot(i).last_good_host_us > 0;
    if (std::all_of(seen.begin(), seen.end(), [](bool s) { return s; })) return "";
    if (steady_s() > camera_deadline) break;
  }
  for (int i = 0; i < cameras_.size(); ++i) {
    if (seen[i]) continue;
    const CameraSlot& s = cameras_.slot(i);
    return fmt::format("camera {}: no frame within {:.3g} s ({}: {})", s.config.name,
                       config_.cell.camera_startup_timeout_s, s.config.backend,
                       s.last_problem.empty() ? "no reason given" : s.last_problem);
  }
  return "";
}

std::string CellController::load_job() {
  try {
    material_ = twin::read_material_file(config_.material_file);
  } catch (const std::exception& e) {
    return fmt::format("material file {}: {}", config_.material_file, e.what());
  }
  try {
    plan_ = twin::read_grasp_plan(config_.plan_file);
  } catch (const std::exception& e) {
    return fmt::format("grasp plan file {}: {}", config_.plan_file, e.what());
  }
  for (const auto& g : plan_.grasps) {
    if (!config_.hardware.find_gripper(g.gripper)) {
      return fmt::format("grasp plan file {}: gripper {} is not in the cell config {}",
                         config_.plan_file, g.gripper, config_.path);
    }
  }
  robots_ = std::make_unique<RobotLink>(bus_, config_.hardware, plan_);
  return "";
}

std::string CellController::wait_for_robots(double deadline_s) {
  const double arm_deadline = std::min(deadline_s, steady_s() + config_.cell.arm_status_timeout_s);
  for (;;) {
    const auto missing = robots_->stale_arms(drivers::host_clock_us(), 1e3 * config_.cell.arm_status_timeout_s);
    if (missing.empty()) break;
    if (steady_s() > arm_deadline) {
      return fmt::format("arm {}: no {} within {:.3g} s", missing.front(),
                         drivers::channels::iiwa_status(missing.front()), config_.cell.arm_status_timeout_s);
    }
    handle_bus(20);
  }
  for (const auto& g : plan_.grasps) {
    const int i = robots_->gripper_index(g.gripper);
    if (robots_->gripper(i).arm < 0) continue;  // the operator holds where the plan says
    const auto jaw = robots_->jaw_position(i);
    const double off = (*jaw - g.hold_position_m).norm();
    if (off > config_.cell.hold_tolerance_m) {
      return fmt::format("gripper {}: jaw at ({:.3f}, {:.3f}, {:.3f}) m is {:.1f} cm from the plan's hold "
                         "position (tolerance {:.1f} cm)",
                         g.gripper, jaw->x(), jaw->y(), jaw->z(), 100 * off, 100 * config_.cell.hold_tolerance_m);
    }
  }
  return "";
}

std::string CellController::first_track(double deadline_s) {
  int attempts = 0;
  std::string last;
  while (steady_s() <= deadline_s || attempts == 0) {
    std::vector<drivers::DepthFrame> frames;
    cameras_.read_all(frames);
    wait_for_next_frames();
    ++attempts;
    last_track_ = tracker_.track(frames, tracking_mesh(twin_->mesh(), prediction_));
    if (last_track_.status != tracking::TrackStatus::kOk) {
      last = std::string(tracking::to_string(last_track_.status)) +
             (last_track_.message.empty() ? "" : ": " + last_track_.message);
      continue;
    }
    if (!config_.tracker.calibration.enabled) return "";
    return calibration_.check_now(tracker_.last_sheet_cloud(), last_track_.cameras_used);
  }
  return fmt::format("tracker: no tracked frame in {} attempts before the start-up timeout ({})", attempts, last);
}

CellState CellController::startup() {
  if (sim_clock_) {
    // Simulation time starts with the world's first SIM_CLOCK; the cell's times count from there.
    advance_clock(0, nullptr);
    if (!clock_problem_.empty()) return fail(clock_problem_);
    started_s_ = steady_s();
  }
  const double deadline = steady_s() + config_.cell.startup_timeout_s;
  status_ = CellStatus{};
  status_.cameras = static_cast<int>(config_.cameras.size());
  status_.state = CellState::kStarting;
  status_.reason = "opening cameras";
  publish_state();
  if (std::string why = open_cameras(deadline); !why.empty()) return fail(why);
  status_.cameras_ok = true;
  status_.cameras_fresh = cameras_.size();
  if (std::string why = load_job(); !why.empty()) return fail(why);
  status_.reason = "waiting for the robots";
  publish_state();
  if (std::string why = wait_for_robots(deadline); !why.empty()) return fail(why);
  status_.robots_ok = status_.grippers_ok = true;
  try {
    const twin::SheetPlacement placement =
        config_.sheet_placement_given ? config_.sheet.placement : placement_under_grasps(plan_);
    twin_ = std::make_unique<CellTwin>(config_.sheet.mesh, material_, plan_, placement);
    twin_->set_background_factorization(config_.cell.twin_background_factorization);
  } catch (const std::exception& e) {
    return fail(fmt::format("twin: {} (grasp plan {}, material {})", e.what(), config_.plan_file,
                            config_.material_file));
  }
  if (std::string why = twin_->initialise(grasp_positions()); !why.empty()) return fail("twin: " + why);
  twin_->set_poisoned(poison_requested_);
  twin_->set_stall(stall_requested_);
  prediction_ = twin_->positions();
  prediction_utime_ = drivers::utime_now();
  twin_cycle_ = status_.cycle + 1;  // the equilibrium is the first cycle's prediction
  status_.twin_ok = true;
  if (std::string why = first_track(deadline); !why.empty()) return fail(why);
  status_.tracker_ok = true;
  bus_.publish(std::string(drivers::channels::kGraspPlan),
               grasp_plan_message(drivers::utime_now(), 1, plan_, config_.hardware));
  status_.state = CellState::kReady;
  status_.reason = "";
  publish_state();
  return status_.state;
}

}  // namespace cell
