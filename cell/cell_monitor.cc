// Assembles the cell's per-cycle messages into monitor records.
#include "cell/cell_monitor.h"

#include <fmt/format.h>

#include "cell/sheet_comparison.h"
#include "drivers/lcm_channels.h"
#include "tracking/point_index.h"

namespace cell {

namespace ch = drivers::channels;
using prepreg_lcm::camera_status_t;
using prepreg_lcm::sheet_state_t;

namespace {

std::string suffix(const std::string& channel, std::string_view prefix) {
  return channel.substr(std::min(channel.size(), prefix.size()));
}

}  // namespace

CellMonitor::CellMonitor(drivers::LcmBus& bus, MonitorOptions options, MonitorSinks sinks,
                         Clock clock)
    : bus_(bus), options_(options), sinks_(std::move(sinks)), clock_(std::move(clock)) {
  auto& s = subscriptions_;
  s.push_back(bus_.subscribe<prepreg_lcm::cell_state_t>(std::string(ch::kCellState),
                                                        [this](const auto& m) { on_state(m); }));
  s.push_back(bus_.subscribe<prepreg_lcm::calibration_t>(std::string(ch::kCellCalibration),
                                                         [this](const auto& m) { on_calibration(m); }));
  s.push_back(bus_.subscribe<prepreg_lcm::diagnosis_t>(std::string(ch::kCellDiagnosis),
                                                       [this](const auto& m) { on_diagnosis(m); }));
  s.push_back(bus_.subscribe<prepreg_lcm::prediction_error_t>(
      std::string(ch::kPredictionError), [this](const auto& m) { on_error(m); }));
  const std::string sheets = std::string(ch::kSheetObserved) + "|" +
                             std::string(ch::kSheetPredicted) + "|" + std::string(ch::kSimTruth);
  s.push_back(bus_.subscribe_with_channel<sheet_state_t>(
      sheets, [this](const std::string& c, const auto& m) { on_sheet(c, m); }));
  s.push_back(bus_.subscribe<prepreg_lcm::sim_clock_t>(std::string(ch::kSimClock),
                                                       [this](const prepreg_lcm::sim_clock_t& m) { sim_clock_ = m; }));
  s.push_back(bus_.subscribe_with_channel<camera_status_t>(
      std::string(ch::kCameraStatusPrefix) + ".*",
      [this](const std::string& c, const camera_status_t& m) {
        cameras_[suffix(c, ch::kCameraStatusPrefix)] = {m, clock_()};
      }));
  s.push_back(bus_.subscribe_with_channel<lcmt_iiwa_status>(
      std::string(ch::kIiwaStatusPrefix) + ".*",
      [this](const std::string& c, const lcmt_iiwa_status&) {
        arms_seen_[suffix(c, ch::kIiwaStatusPrefix)] = clock_();
      }));
  s.push_back(bus_.subscribe_with_channel<prepreg_lcm::gripper_status_t>(
      std::string(ch::kGripperStatusPrefix) + ".*",
      [this](const std::string& c, const prepreg_lcm::gripper_status_t&) {
        grippers_seen_[suffix(c, ch::kGripperStatusPrefix)] = clock_();
      }));
}

CellMonitor::~CellMonitor() {
  for (auto id : subscriptions_) bus_.unsubscribe(id);
}

void CellMonitor::on_calibration(const prepreg_lcm::calibration_t& msg) {
  CalibrationEvent e;
  e.seen_utime = clock_();
  e.calibration_id = msg.calibration_id;
  e.verdict = msg.verdict;
  e.reason = msg.reason;
  for (int i = 0; i < msg.num_parameters; ++i) {
    e.parameters.push_back(fmt::format("{} {:.4g} [{:.4g}, {:.4g}]{}", msg.parameter_names[i], msg.values[i],
                                       msg.lower95[i], msg.upper95[i], msg.determined[i] ? "" : " not determined"));
  }
  e.held_out_before_m = msg.held_out_error_before_m;
  e.held_out_after_m = msg.held_out_error_after_m;
  e.states_fitted = msg.states_fitted;
  e.seconds = msg.seconds;
  summary_.add_calibration(e);
  if (sinks_.calibration) sinks_.calibration(e);
}

void CellMonitor::on_diagnosis(const prepreg_lcm::diagnosis_t& msg) {
  DiagnosisEvent e;
  e.seen_utime = clock_();
  e.diagnosis_id = msg.diagnosis_id;
  e.verdict = msg.verdict;
  e.effect = msg.effect;
  e.adoption = msg.adoption;
  e.reason = msg.reason;
  e.base_held_out_m = msg.base_held_out_mean_m;
  e.effect_held_out_m = msg.effect_held_out_mean_m;
  e.states = msg.states;
  e.seconds = msg.seconds;
  summary_.add_diagnosis(e);
  if (sinks_.diagnosis) sinks_.diagnosis(e);
}

void CellMonitor::on_state(const prepreg_lcm::cell_state_t& msg) {
  if (!state_ || *state_ != msg.state) {
    StateChange change{clock_(), msg.cycle_id, state_, msg.state, msg.reason};
    summary_.add_state_change(change);
    if (sinks_.state_change) sinks_.state_change(change);
  }
  state_ = msg.state;
  reason_ = msg.reason;
  if (msg.cycle_id < 0) {  // start-up: no cycle yet
    if (msg.state == prepreg_lcm::cell_state_t::STATE_STARTING &&
        (pending_ || last_completed_ >= 0)) {
      // The cell started again: its cycle ids begin anew.
      complete();
      last_completed_ = -1;
      summary_.start_new_run();
    }
    return;
  }
  CycleRecord* r = record_for(msg.cycle_id);
  if (!r) return;  // a state change published again for a finished cycle
  r->state = msg.state;
  r->reason = msg.reason;
  complete();
}

void CellMonitor::on_error(const prepreg_lcm::prediction_error_t& msg) {
  CycleRecord* r = record_for(msg.cycle_id);
  if (!r) return;
  r->error = ErrorFigures{msg.num_compared, msg.mean_m, msg.max_m, msg.score_m};
  r->latency_ms = 1e-3 * static_cast<double>(msg.utime - msg.frames_utime);
}

void CellMonitor::on_sheet(const std::string& channel, const sheet_state_t& msg) {
  if (channel == ch::kSimTruth) {
    if (!options_.truth) return;
    truth_ = msg;
    truth_index_stale_ = true;
    return;
  }
  CycleRecord* r = record_for(msg.cycle_id);
  if (!r) return;
  if (channel == ch::kSheetPredicted) {
    predicted_ = msg;
    return;
  }
  observed_ = msg;
  r->coverage = msg.coverage;
  r->num_vertices = msg.num_vertices;
  r->observed_vertices = 0;
  for (bool seen : msg.vertex_observed) r->observed_vertices += seen ? 1 : 0;
}

CycleRecord* CellMonitor::record_for(std::int64_t cycle_id) {
  if (pending_ && cycle_id > pending_->cycle_id) complete();
  if (pending_ && cycle_id == pending_->cycle_id) return &*pending_;
  if (cycle_id <= last_completed_ || pending_) {
    summary_.count_late_message();
    return nullptr;
  }
  pending_.emplace();
  pending_->cycle_id = cycle_id;
  observed_.reset();
  predicted_.reset();
  return &*pending_;
}

void CellMonitor::complete() {
  if (!pending_) return;
  CycleRecord& r = *pending_;
  r.seen_utime = clock_();
  if (sim_clock_) {
    r.real_time_factor = sim_clock_->real_time_factor;
    r.clock_held = sim_clock_->state == prepreg_lcm::sim_clock_t::STATE_HELD;
  }
  if (!r.state && state_) {  // CELL_STATE of this cycle lost: the latest state known
    r.state = state_;
    r.reason = reason_;
  }
  if (options_.recompute && observed_ && predicted_) {
    r.recomputed = recompute_prediction_error(*observed_, *predicted_);
  }
  compare_with_truth(r);
  fill_devices(r);
  r.bus = bus_.counters();
  summary_.add_cycle(r);
  last_completed_ = r.cycle_id;
  CycleRecord done = std::move(r);
  pending_.reset();
  if (sinks_.cycle) sinks_.cycle(done);
}

void CellMonitor::flush() { complete(); }

void CellMonitor::compare_with_truth(CycleRecord& r) {
  if (!truth_) return;
  if (truth_index_stale_) {
    if (!truth_index_) truth_index_ = std::make_unique<tracking::PointIndex>();
    // One thread: the monitor must not compete with the cell for cores.
    truth_index_->build(sheet_points(*truth_, false), 1);
    truth_index_stale_ = false;
  }
  if (predicted_)
    r.twin_truth_mean_m = mean_nearest_distance_m(sheet_points(*predicted_, false), *truth_index_);
  if (observed_)
    r.tracked_truth_mean_m = mean_nearest_distance_m(sheet_points(*observed_, true), *truth_index_);
}

void CellMonitor::fill_devices(CycleRecord& r) const {
  const std::int64_t now = clock_();
  for (const auto& [name, seen] : cameras_) {
    const camera_status_t& c = seen.first;
    const double age_ms = 1e-3 * static_cast<double>(now - seen.second);
    ++r.cameras_total;
    std::string why;
    if (age_ms > options_.camera_silent_ms) {
      why = "silent";
    } else if (c.state != camera_status_t::STATE_ACTIVE &&
               c.state != camera_status_t::STATE_DEGRADED) {
      static const char* const kStates[] = {"UNCONFIGURED", "CONFIGURED", "ACTIVE", "DEGRADED",
                                            "LOST"};
      why = c.state >= 0 && c.state <= 4 ? kStates[c.state] : "state " + std::to_string(c.state);
    } else if (c.stale) {
      why = "stale";
    } else if (c.frozen) {
      why = "frozen";
    }
    if (why.empty()) {
      ++r.cameras_ok;
    } else {
      // The configured name (the channel suffix is upper-cased).
      r.cameras_lost.push_back((c.name.empty() ? name : c.name) + " (" + why + ")");
    }
  }
  for (const auto& [name, t] : arms_seen_)
    r.arms.push_back({name, 1e-3 * static_cast<double>(now - t)});
  for (const auto& [name, t] : grippers_seen_)
    r.grippers.push_back({name, 1e-3 * static_cast<double>(now - t)});
}

}  // namespace cell
