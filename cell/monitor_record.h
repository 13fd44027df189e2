#pragma once
// What the terminal monitor knows about one cell cycle, assembled from the messages the cell
// publishes for it (CELL_STATE, PREDICTION_ERROR, SHEET_OBSERVED, SHEET_PREDICTED) plus the
// device status channels and, on fake hardware, the world's true sheet. Plain data: the monitor
// fills it, the printer formats it, the summary accumulates it.

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/lcm_bus.h"

namespace cell {

struct ErrorFigures {
  int compared = 0;  // vertices compared (count)
  double mean_m = 0.0;
  double max_m = 0.0;
  double score_m = 0.0;  // mean + 0.5 max
};

// A device status channel's suffix (arm, gripper) and how long ago its last message arrived.
struct DeviceAge {
  std::string name;
  double age_ms = 0.0;
};

struct CycleRecord {
  std::int64_t cycle_id = -1;
  std::int64_t seen_utime = 0;       // monitor clock (us) when the record was completed
  std::optional<std::int8_t> state;  // cell_state_t::STATE_*
  std::string reason;
  std::optional<ErrorFigures> error;       // as published on PREDICTION_ERROR
  double latency_ms = NAN;                 // PREDICTION_ERROR utime - frames_utime
  std::optional<ErrorFigures> recomputed;  // from SHEET_OBSERVED + SHEET_PREDICTED
  std::optional<double> coverage;          // SHEET_OBSERVED coverage, 0..1
  int observed_vertices = 0;               // vertices flagged observed (count)
  int num_vertices = 0;
  // Nearest distance from each predicted / observed vertex to the true sheet's vertices, mean
  // (m); only on fake hardware (SIM_SHEET_TRUTH).
  std::optional<double> twin_truth_mean_m;
  std::optional<double> tracked_truth_mean_m;
  int cameras_ok = 0;
  int cameras_total = 0;
  std::vector<std::string> cameras_lost;  // "name (why)"
  std::vector<DeviceAge> arms;
  std::vector<DeviceAge> grippers;
  drivers::BusCounters bus;  // the monitor bus's drop counters when the record was completed
  // The fake world's simulation clock (SIM_CLOCK), when one runs: its real-time factor and
  // whether it was held, as last heard.
  std::optional<double> real_time_factor;
  bool clock_held = false;
};

// A CELL_CALIBRATION message as the monitor keeps it (cell/learning/in_situ_calibration.h).
struct CalibrationEvent {
  std::int64_t seen_utime = 0;
  std::int64_t calibration_id = 0;
  std::string verdict, reason;
  std::vector<std::string> parameters;  // "bending_Nm 0.00061 [0.00052, 0.00071]" (not determined: marked)
  double held_out_before_m = 0.0, held_out_after_m = 0.0;  // NaN when not simulated
  int states_fitted = 0;
  double seconds = 0.0;
};

// A CELL_DIAGNOSIS message as the monitor keeps it (cell/learning/in_situ_diagnosis.h).
struct DiagnosisEvent {
  std::int64_t seen_utime = 0;
  std::int64_t diagnosis_id = 0;
  std::string verdict, effect, adoption, reason;
  double base_held_out_m = 0.0, effect_held_out_m = 0.0;  // NaN when not simulated
  int states = 0;
  double seconds = 0.0;
};

struct StateChange {
  std::int64_t seen_utime = 0;
  std::int64_t cycle_id = -1;
  std::optional<std::int8_t> from;  // none for the first state seen
  std::int8_t to = 0;
  std::string reason;
};

}  // namespace cell
