#pragma once
// The terminal monitor's logic: subscribes to the cell's channels on an LcmBus and turns the
// messages of each cycle into one CycleRecord, plus a StateChange whenever CELL_STATE changes.
//
// A cycle's record is complete when its CELL_STATE arrives (the cell publishes it last in a
// cycle) or, if that was lost, when a message of a later cycle arrives, or at flush(). Messages
// of a cycle already completed are late: counted, not used. Malformed messages never reach the
// monitor: the LcmBus drops and counts them, and each record carries the bus counters.
//
// Times: device ages and the cycle rate use the monitor clock (microseconds), the wall clock
// when live and the log's timestamps on replay.

#include <cstdint>
#include <functional>
#include <lcmt_iiwa_status.hpp>
#include <map>
#include <memory>
#include <optional>
#include <prepreg_lcm/calibration_t.hpp>
#include <prepreg_lcm/diagnosis_t.hpp>
#include <prepreg_lcm/camera_status_t.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <string>
#include <vector>

#include "cell/monitor_record.h"
#include "cell/monitor_summary.h"
#include "drivers/lcm_bus.h"

namespace tracking {
class PointIndex;
}

namespace cell {

struct MonitorOptions {
  bool recompute = true;  // recompute the error from SHEET_OBSERVED + SHEET_PREDICTED
  bool truth = true;      // compare with SIM_SHEET_TRUTH when it is on the bus
  // A camera whose status is older than this (monitor clock) counts as lost ("silent").
  double camera_silent_ms = 2000.0;
};

struct MonitorSinks {
  std::function<void(const CycleRecord&)> cycle;
  std::function<void(const StateChange&)> state_change;
  std::function<void(const CalibrationEvent&)> calibration;  // CELL_CALIBRATION
  std::function<void(const DiagnosisEvent&)> diagnosis;      // CELL_DIAGNOSIS
};

class CellMonitor {
 public:
  using Clock = std::function<std::int64_t()>;

  // Subscribes on `bus` (which must outlive the monitor). Throws if a subscription is refused.
  CellMonitor(drivers::LcmBus& bus, MonitorOptions options, MonitorSinks sinks,
              Clock clock = drivers::utime_now);
  ~CellMonitor();
  CellMonitor(const CellMonitor&) = delete;
  CellMonitor& operator=(const CellMonitor&) = delete;

  // Completes the pending cycle, if any (at exit).
  void flush();
  const MonitorSummary& summary() const { return summary_; }

 private:
  void on_state(const prepreg_lcm::cell_state_t& msg);
  void on_calibration(const prepreg_lcm::calibration_t& msg);
  void on_diagnosis(const prepreg_lcm::diagnosis_t& msg);
  void on_error(const prepreg_lcm::prediction_error_t& msg);
  void on_sheet(const std::string& channel, const prepreg_lcm::sheet_state_t& msg);
  // The record of `cycle_id`, completing older pending ones; nullptr when the cycle is done.
  CycleRecord* record_for(std::int64_t cycle_id);
  void complete();
  void fill_devices(CycleRecord& r) const;
  void compare_with_truth(CycleRecord& r);

  drivers::LcmBus& bus_;
  MonitorOptions options_;
  MonitorSinks sinks_;
  Clock clock_;
  std::vector<drivers::LcmBus::SubscriptionId> subscriptions_;

  std::optional<CycleRecord> pending_;
  std::int64_t last_completed_ = -1;
  std::optional<prepreg_lcm::sheet_state_t> observed_, predicted_;  // of the pending cycle
  std::optional<prepreg_lcm::sheet_state_t> truth_;                 // latest
  std::unique_ptr<tracking::PointIndex> truth_index_;
  bool truth_index_stale_ = true;
  std::optional<std::int8_t> state_;
  std::string reason_;
  std::map<std::string, std::pair<prepreg_lcm::camera_status_t, std::int64_t>> cameras_;
  std::map<std::string, std::int64_t> arms_seen_, grippers_seen_;  // suffix -> monitor utime
  MonitorSummary summary_;
  std::optional<prepreg_lcm::sim_clock_t> sim_clock_;  // latest SIM_CLOCK
};

}  // namespace cell
