#include "cell/cell_controller.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "drivers/lcm_channels.h"

namespace cell {

double steady_s() { return 1e-6 * static_cast<double>(drivers::host_clock_us()); }

namespace {
// The cell checks the cameras' calibration itself, off the cycle (calibration_monitor.h).
tracking::TrackerConfig without_calibration_check(tracking::TrackerConfig c) {
  c.calibration.enabled = false;
  return c;
}

// The cameras' fastest configured frame rate (1/s); 0 when no camera says.
int fastest_fps(const std::vector<drivers::CameraConfig>& cameras) {
  int fps = 0;
  for (const auto& c : cameras) fps = std::max(fps, c.depth_mode.fps);
  return fps;
}

// The frame period the pacer locks cycles to (s): 0 when no camera says, and on the simulation
// clock, where the cycles keep their own period exactly (a frame's arrival there is when the
// cycle reads it, so locking to it would only add the lock's slack every cycle).
double frame_period_s(const CellSettings& cell, const std::vector<drivers::CameraConfig>& cameras) {
  const int fps = fastest_fps(cameras);
  return cell.clock == drivers::ClockSource::kSim || fps <= 0 ? 0.0 : 1.0 / fps;
}
}  // namespace

CellController::CellController(CellConfig config, drivers::LcmBus& bus, bool fault_injection)
    : config_(std::move(config)),
      pacer_(1.0 / config_.cell.cycle_hz, frame_period_s(config_.cell, config_.cameras)),
      bus_(bus),
      sim_clock_(config_.cell.clock == drivers::ClockSource::kSim
                     ? std::make_unique<drivers::SimClockClient>(bus, std::string(kLockstepClientName))
                     : nullptr),
      fault_injection_(fault_injection),
      tracker_(without_calibration_check(config_.tracker)),
      calibration_(config_.tracker.calibration),
      calibration_worker_(config_.learning.priority),
      branch_worker_(config_.learning.priority),
      twin_worker_(config_.cell.twin_priority) {
  status_.cameras = static_cast<int>(config_.cameras.size());
  subscriptions_.push_back(bus_.subscribe<prepreg_lcm::sheet_state_t>(
      std::string(drivers::channels::kSimTruth), [this](const prepreg_lcm::sheet_state_t& msg) {
        truth_.resize(msg.num_vertices);
        for (int i = 0; i < msg.num_vertices; ++i) truth_[i] = twin::Vec3(msg.x_m[i], msg.y_m[i], msg.z_m[i]);
        truth_host_us_ = drivers::host_clock_us();
      }));
  subscriptions_.push_back(bus_.subscribe<prepreg_lcm::sim_fault_t>(
      std::string(drivers::channels::kSimFault), [this](const prepreg_lcm::sim_fault_t& msg) {
        // Only fake hardware injects faults, and only the twin's are the cell's to act on.
        if (!fault_injection_ || msg.target != "twin") return;
        if (msg.fault == "diverge") {
          if (twin_) twin_->set_poisoned(msg.active);
          poison_requested_ = msg.active;
        } else if (msg.fault == "slow") {
          const auto stall = std::chrono::milliseconds(msg.active ? static_cast<int>(3e3 * period_s()) : 0);
          if (twin_) twin_->set_stall(stall);
          stall_requested_ = stall;
        } else {
          ++faults_dropped_;  // a twin fault the cell does not know: dropped, counted
        }
      }));
}

bool CellController::shut_down_background(std::chrono::milliseconds timeout) {
  calibration_cancelled_->store(true);  // a running fit ends within one Newton iteration
  const bool calibration = calibration_worker_.finish_or_let_go(timeout);
  const bool branch = branch_worker_.finish_or_let_go(timeout);
  return calibration && branch;
}

CellController::~CellController() {
  shut_down_background(std::chrono::seconds(2));
  for (auto id : subscriptions_) bus_.unsubscribe(id);
  robots_.reset();
  cameras_.close();
}

std::int64_t CellController::next_cycle_start_us(std::int64_t last_start_us, const CycleReport& last) const {
  return pacer_.next_start_us(last_start_us, last.newest_frame_host_us, drivers::host_clock_us());
}

void CellController::handle_bus(int ms) {
  if (sim_clock_ && ms > 0) {
    advance_clock(sim_clock_->now_us() + 1000 * static_cast<std::int64_t>(ms), nullptr);
  } else {
    // handle_for dispatches everything already waiting; a zero wait only drains.
    bus_.handle_for(std::chrono::milliseconds(ms));
  }
  while (bus_.handle_for(std::chrono::milliseconds(0)).messages > 0) {
  }
}

void CellController::wait_until(std::int64_t until_us, const std::atomic<bool>* stop) {
  if (sim_clock_) {
    advance_clock(until_us, stop);
    handle_bus(0);
    return;
  }
  while (!(stop && stop->load())) {
    const std::int64_t left_ms = (until_us - drivers::host_clock_us()) / 1000;
    if (left_ms <= 0) break;
    handle_bus(static_cast<int>(left_ms));
  }
}

void CellController::advance_clock(std::int64_t until_us, const std::atomic<bool>* stop) {
  if (sim_clock_->advance_to(until_us, config_.cell.sim_clock_timeout_s, stop)) {
    clock_problem_.clear();
  } else if (!(stop && stop->load())) {
    clock_problem_ = fmt::format("simulation clock: no SIM_CLOCK for {:.1f} s (is the fake world running?)",
                                 sim_clock_->silent_s());
  }
}

void CellController::wait_for_next_frames() {
  if (!sim_clock_) {
    handle_bus(0);
    return;
  }
  const int fps = fastest_fps(config_.cameras);
  handle_bus(fps > 0 ? std::max(1, static_cast<int>(std::ceil(1000.0 / fps))) : 1);
}

void CellController::stop(const std::string& why) {
  calibration_cancelled_->store(true);
  status_.state = CellState::kStopped;
  status_.reason = why;
  publish_state();
  cameras_.close();
}

std::uint64_t CellController::dropped_messages() const {
  std::uint64_t n = faults_dropped_ + (robots_ ? robots_->dropped_statuses() : 0);
  for (auto id : subscriptions_) {
    const drivers::BusCounters c = bus_.counters(id);
    n += c.decode_failures + c.rejected;
  }
  return n;
}

bool CellController::set_goal(const std::string& gripper, const twin::Vec3& to_m) {
  if (!robots_) return false;
  const int g = robots_->gripper_index(gripper);
  if (g < 0 || robots_->gripper(g).arm < 0) return false;  // the operator does not move
  robots_->set_goal(g, to_m);
  return true;
}

bool CellController::at_goal(const std::string& gripper) const {
  const int g = robots_ ? robots_->gripper_index(gripper) : -1;
  return g >= 0 && robots_->at_goal(g);
}

bool CellController::request_release(const std::string& gripper) {
  if (!robots_ || !twin_) return false;
  const int g = robots_->gripper_index(gripper);
  const int k = plan_.index_of(gripper);
  if (g < 0 || k < 0) return false;
  releases_.push_back(Release{k, g, false, 0, false});
  return true;
}

bool CellController::released(const std::string& gripper) const {
  const int k = plan_.index_of(gripper);
  return k >= 0 && twin_ && !twin_->engaged(k);
}

}  // namespace cell
