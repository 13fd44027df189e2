#pragma once
// Text of the terminal monitor: one line per cycle, one per state change, and the summary.
// Lengths in mm, times in ms, so a line reads at a glance.

#include <string>

#include "cell/monitor_record.h"
#include "cell/monitor_summary.h"

namespace cell {

// "RUNNING", "SAFE_HOLD", ... ("STATE_<n>" for an unknown value).
std::string cell_state_name(std::int8_t state);

// e.g. "cycle 42 RUNNING err mean 3.10 max 8.20 score 7.20 mm (n 310) re 3.10/8.20 cov 0.86
// (310/360) lat 41.0 ms cams 3/3 arms LEFT 12 RIGHT 9 ms grippers G1 15 ms drops 0/0/0"
std::string format_cycle(const CycleRecord& record);
std::string format_state_change(const StateChange& change);
// "calibration 2: adopted (3 states fitted, 41.0 s), held-out state 14.1 -> 9.8 mm mean; bending_Nm ...: why".
std::string format_calibration(const CalibrationEvent& event);
// "diagnosis 1: effect clamp_grip, adopted (4 states, 310.2 s), held-out state 12.1 -> 6.3 mm mean: why".
std::string format_diagnosis(const DiagnosisEvent& event);
// Multi-line, ends with a newline.
std::string format_summary(const MonitorSummary& summary, const drivers::BusCounters& bus);

}  // namespace cell
