#pragma once
// Totals over a monitoring session, printed at exit: cycles seen, the cycle ids that never
// arrived, error percentiles, cycle rate, state changes, and how often the recomputed error
// disagreed with the published one.

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cell/monitor_record.h"

namespace cell {

struct Percentiles {
  double p50 = 0.0, p90 = 0.0, p99 = 0.0, max = 0.0;
};

class MonitorSummary {
 public:
  // Published and recomputed errors further apart than this (m) count as a mismatch: the
  // message carries float32, so ~1e-7 relative is the best agreement possible.
  static constexpr double kMismatchTolerance_m = 1e-5;

  void add_cycle(const CycleRecord& record);
  void add_state_change(const StateChange& change) { state_changes_.push_back(change); }
  void add_calibration(const CalibrationEvent& event) { calibrations_.push_back(event); }
  void add_diagnosis(const DiagnosisEvent& event) { diagnoses_.push_back(event); }
  void count_late_message() { ++late_messages_; }
  // The cell started again (cycle ids restart at 0): the ids seen so far are closed as a run.
  void start_new_run();

  int cycles() const { return prior_cycles_ + static_cast<int>(ids_.size()); }
  int restarts() const { return restarts_; }
  std::int64_t first_id() const { return ids_.empty() ? -1 : *ids_.begin(); }
  std::int64_t last_id() const { return ids_.empty() ? -1 : *ids_.rbegin(); }
  // first_id, last_id and missing_ranges are those of the current run; missing_count is the total.
  // Ids between the first and last seen that were never seen, as [first, last] ranges.
  std::vector<std::pair<std::int64_t, std::int64_t>> missing_ranges() const;
  std::int64_t missing_count() const;
  // Cycles per second of monitor clock between the first and last record (0 if < 2 records).
  double rate_hz() const;
  Percentiles mean_error_m() const { return percentiles(means_m_); }
  Percentiles score_error_m() const { return percentiles(scores_m_); }
  int cycles_with_error() const { return static_cast<int>(means_m_.size()); }
  int recomputed() const { return recomputed_; }
  int mismatches() const { return mismatches_; }
  double worst_mismatch_m() const { return worst_mismatch_m_; }
  std::uint64_t late_messages() const { return late_messages_; }
  const std::vector<StateChange>& state_changes() const { return state_changes_; }
  const std::vector<CalibrationEvent>& calibrations() const { return calibrations_; }
  const std::vector<DiagnosisEvent>& diagnoses() const { return diagnoses_; }
  const drivers::BusCounters& last_bus() const { return last_bus_; }
  // The simulation clock's real-time factor over the cycles that heard one (empty: none did).
  Percentiles real_time_factor() const { return percentiles(real_time_factors_); }
  int cycles_with_clock() const { return static_cast<int>(real_time_factors_.size()); }

 private:
  static Percentiles percentiles(std::vector<double> values);

  std::vector<double> real_time_factors_;
  std::set<std::int64_t> ids_;  // current run
  int prior_cycles_ = 0, restarts_ = 0;
  std::int64_t prior_missing_ = 0;
  std::int64_t first_seen_utime_ = 0, last_seen_utime_ = 0;
  std::vector<double> means_m_, scores_m_;
  int recomputed_ = 0, mismatches_ = 0;
  double worst_mismatch_m_ = 0.0;
  std::uint64_t late_messages_ = 0;
  std::vector<StateChange> state_changes_;
  std::vector<CalibrationEvent> calibrations_;
  std::vector<DiagnosisEvent> diagnoses_;
  drivers::BusCounters last_bus_;
};

}  // namespace cell
