// CellController's cycle: cameras -> (twin step beside tracker) -> publish -> watchdog -> commands.
#include <fmt/format.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <optional>
#include <utility>

#include "cell/cell_controller.h"
#include "cell/sheet_compare.h"
#include "drivers/lcm_channels.h"

namespace cell {
namespace {
double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
}  // namespace

std::vector<twin::Vec3> CellController::grasp_positions() const {
  std::vector<twin::Vec3> out;
  for (const auto& g : plan_.grasps) {
    const int i = robots_->gripper_index(g.gripper);
    const auto jaw = i >= 0 ? robots_->jaw_position(i) : std::nullopt;
    out.push_back(jaw ? *jaw : g.hold_position_m);
  }
  return out;
}

void CellController::publish_state() {
  bus_.publish(std::string(drivers::channels::kCellState), cell_state(drivers::utime_now(), status_));
}

void CellController::publish_cameras(std::int64_t now_us) {
  const std::int64_t epoch_minus_host = drivers::utime_now() - now_us;
  for (int i = 0; i < cameras_.size(); ++i) {
    const CameraSlot& s = cameras_.slot(i);
    const bool stale = !cameras_.fresh(i, now_us, config_.cell.camera_stale_ms);
    const std::int64_t last = s.last_good_host_us > 0 ? s.last_good_host_us + epoch_minus_host : 0;
    bus_.publish(drivers::channels::camera_status(s.config.name),
                 camera_status(drivers::utime_now(), s.config.name, cameras_.health(i), stale,
                               s.last_status == drivers::ReadStatus::kFrozen, last));
  }
}

void CellController::update_releases(std::int64_t now_us) {
  for (auto& r : releases_) {
    if (r.done || !r.commanded) continue;
    const GripperLink& g = robots_->gripper(r.gripper);
    const bool reported_open = g.last_status_host_us > r.commanded_host_us && !g.holding;
    const bool no_status = g.last_status_host_us <= r.commanded_host_us &&
                           (now_us - r.commanded_host_us) > 1e6 * config_.cell.release_timeout_s;
    if (reported_open || no_status) {
      twin_->release(r.grasp);
      r.done = true;
    }
  }
}

void CellController::submit_twin_work() {
  // One step from the cycle the twin's state is for to the next cycle, with the clamps where
  // the grippers are (measured); after a failure, a fresh static equilibrium there instead.
  const bool step = twin_problem_.empty() && !pending_material_ && !pending_state_;
  const std::int64_t next_cycle = status_.cycle + 1;
  const double dt_s = static_cast<double>(std::max<std::int64_t>(next_cycle - twin_cycle_, 1)) * period_s();
  twin_cycle_ = next_cycle;
  const std::int64_t state_utime = drivers::utime_now() + (step ? static_cast<std::int64_t>(1e6 * period_s()) : 0);
  const int omp_threads = omp_get_max_threads();
  // A newly adopted material goes in with a static equilibrium under it (cell_twin.h), from
  // the twin's state when it is healthy.
  std::optional<twin::Material> material;
  std::optional<twin::VecX> reseed;
  if (twin_problem_.empty()) {
    material = std::exchange(pending_material_, std::nullopt);
    if (!material) reseed = std::exchange(pending_state_, std::nullopt);
  }
  twin_work_ = twin_worker_.submit([this, step, dt_s, state_utime, omp_threads, material, reseed,
                                    grasps = grasp_positions()] {
    omp_set_num_threads(omp_threads);
    TwinWork work;
    work.stepped = step;
    work.dt_s = dt_s;
    work.state_utime = state_utime;
    if (step) {
      work.step = twin_->step(dt_s, grasps);
    } else if (material) {
      work.swapped = true;
      work.initialise_problem = twin_->set_material(*material, grasps);
    } else if (reseed) {
      work.reseeded = true;
      twin_->adopt_state(*reseed);
    } else {
      work.initialise_problem = twin_->initialise(grasps);
    }
    return work;
  });
}

void CellController::collect_twin_work(CycleReport& report) {
  const TwinWork work = twin_work_.get();  // the worker is done with the twin until the next submit
  if (work.stepped) {
    report.twin_step_ms = work.step.step_ms;
    report.twin_stepped = work.step.ok;
    report.twin_substeps = work.step.substeps;
    report.twin_step_dt_s = work.dt_s;
    if (work.step.ok) {
      prediction_ = twin_->positions();
      prediction_utime_ = work.state_utime;
    } else {
      twin_problem_ = work.step.message;
    }
  } else if (work.reseeded) {
    ++status_.twin_reseeds;
    prediction_ = twin_->positions();
    prediction_utime_ = work.state_utime;
    tracker_.forget_last_track();
  } else if (work.swapped && !work.initialise_problem.empty()) {
    // The twin kept its material and state (cell_twin.h): it stays healthy; the cell says why.
    material_swap_problem_ = work.initialise_problem;
  } else if (work.initialise_problem.empty()) {
    if (work.swapped) {
      material_ = twin_->material();
      material_swap_problem_.clear();
    }
    twin_problem_.clear();
    prediction_ = twin_->positions();
    prediction_utime_ = work.state_utime;
    // The new equilibrium may be far from the last prediction: the tracker's next fit starts
    // from it with the full gates rather than from the last track's correction.
    tracker_.forget_last_track();
  } else {
    twin_problem_ = "re-initialisation failed: " + work.initialise_problem;
  }
}

CycleReport CellController::cycle() {
  const auto t0 = std::chrono::steady_clock::now();
  CycleReport report;
  report.cycle = ++status_.cycle;
  handle_bus(0);

  std::vector<drivers::DepthFrame> frames;
  cameras_.read_all(frames);
  report.frames = static_cast<int>(frames.size());
  std::int64_t newest_host_us = 0;
  for (const auto& f : frames) newest_host_us = std::max(newest_host_us, f.host_time_us);
  const std::int64_t now_us = drivers::host_clock_us();
  const std::int64_t epoch_minus_host = drivers::utime_now() - now_us;
  report.newest_frame_host_us = newest_host_us;
  if (newest_host_us > 0) report.frame_age_ms = 1e-3 * static_cast<double>(now_us - newest_host_us);

  // 1. The twin runs on its worker thread beside the tracker: it needs nothing the tracker makes.
  // A job that has finished is taken up now (in lockstep, the last cycle's always has). While
  // one runs the twin is not touched here: releases wait, and the cycle compares and publishes
  // the newest finished state. When the twin is idle the next job starts, so a cycle costs the
  // tracker's time, not the twin's.
  if (twin_work_.valid() && twin_work_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    collect_twin_work(report);
  }
  const bool twin_idle = !twin_work_.valid();
  if (twin_idle) update_releases(now_us);
  const bool twin_ok = twin_ && twin_problem_.empty();
  report.twin_ok = twin_ok;
  const twin::VecX predicted = prediction_;
  if (twin_ && twin_idle) submit_twin_work();

  // 2. Tracking, from the twin's prediction (when it has one).
  if (twin_ok && !frames.empty()) {
    last_track_ = tracker_.track(frames, tracking_mesh(twin_->mesh(), predicted));
    report.tracker_ms = last_track_.times.total_ms;
    report.tracked = last_track_.status == tracking::TrackStatus::kOk;
    if (report.tracked) {
      // The calibration check judges a still sheet only (calibration_monitor.h).
      const double speed = median_vertex_speed_m_s(last_tracked_m_, last_track_.vertices_m,
                                                   1e-6 * static_cast<double>(newest_host_us - last_tracked_frame_us_));
      calibration_.after_tracked_cycle(tracker_.last_sheet_cloud(), last_track_.cameras_used, speed);
      last_tracked_m_ = last_track_.vertices_m;
      last_tracked_frame_us_ = newest_host_us;
    }
  }
  status_.tracker_ok = report.tracked;
  learn_from_cycle(report);

  // 3. Publish what the cycle saw and what the twin predicted for it.
  if (twin_ok) {
    bus_.publish(std::string(drivers::channels::kSheetPredicted),
                 predicted_sheet(prediction_utime_, report.cycle, predicted));
  }
  if (report.tracked) {
    const std::int64_t frames_utime = newest_host_us + epoch_minus_host;
    bus_.publish(std::string(drivers::channels::kSheetObserved), observed_sheet(frames_utime, report.cycle, last_track_));
    report.error = vertex_error(last_track_);
    report.alg1_mean_m = last_track_.prediction_error.mean_m;
    report.alg1_max_m = last_track_.prediction_error.max_m;
    bus_.publish(std::string(drivers::channels::kPredictionError),
                 prediction_error(drivers::utime_now(), report.cycle, frames_utime, prediction_utime_, report.error));
    report.latency_ms = 1e-3 * static_cast<double>(drivers::host_clock_us() - newest_host_us);
  }
  publish_cameras(now_us);

  // In lockstep the cycle waits for its twin job, so the watchdog judges this cycle's step.
  if (config_.cell.twin_lockstep && twin_work_.valid()) collect_twin_work(report);

  // 4. Watchdog, state, and robot commands only while it allows them.
  // Statuses that arrived during the cycle count: they are stamped when handled.
  handle_bus(0);
  WatchdogInputs in;
  in.cameras = cameras_.size();
  in.min_cameras = config_.cell.min_cameras;
  const std::int64_t after_us = drivers::host_clock_us();
  for (int i = 0; i < cameras_.size(); ++i) {
    // Judged at read time: a slow tracker or twin must not make a camera that just delivered
    // look stale.
    if (cameras_.fresh(i, now_us, config_.cell.camera_stale_ms)) continue;
    const CameraSlot& s = cameras_.slot(i);
    in.lost_cameras.push_back(s.config.name + " (" + (s.last_problem.empty() ? "no fresh frame" : s.last_problem) + ")");
  }
  in.calibration_problem = calibration_.problem();
  in.twin_ok = twin_problem_.empty();
  in.twin_problem = twin_problem_;
  in.stale_arms = robots_->stale_arms(after_us, config_.cell.robot_status_timeout_ms);
  in.robot_status_timeout_ms = config_.cell.robot_status_timeout_ms;
  in.clock_problem = clock_problem_;
  const WatchdogVerdict verdict = judge(in);
  status_.state = verdict.state;
  status_.reason = verdict.reason;
  status_.cameras_ok = verdict.cameras_ok;
  status_.twin_ok = verdict.twin_ok;
  status_.robots_ok = verdict.robots_ok;
  status_.grippers_ok = true;
  status_.cameras_fresh = in.cameras - static_cast<int>(in.lost_cameras.size());
  publish_state();
  if (may_command(status_.state)) {
    robots_->advance_targets(period_s(), config_.cell.move_speed_m_s);
    robots_->command_arms(period_s(), config_.cell.joint_speed_scale);
    for (auto& r : releases_) {
      if (r.commanded) continue;
      if (robots_->open_gripper(r.gripper)) {
        r.commanded = true;
        r.commanded_host_us = drivers::host_clock_us();
      }
    }
    report.commanded = true;
  }
  report.state = status_.state;
  report.cycle_ms = ms_between(t0, std::chrono::steady_clock::now());
  return report;
}

}  // namespace cell
