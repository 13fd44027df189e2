// Monitor text.
#include "cell/monitor_format.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>

namespace cell {

namespace {

std::string ages(const char* label, const std::vector<DeviceAge>& devices) {
  if (devices.empty()) return "";
  std::string s = fmt::format(" {}", label);
  for (const DeviceAge& d : devices) s += fmt::format(" {} {:.0f}", d.name, d.age_ms);
  return s + " ms";
}

std::string drops(const drivers::BusCounters& c) {
  // decode failures / rejected by the checks / callback errors
  return fmt::format(" drops {}/{}/{}", c.decode_failures, c.rejected, c.callback_errors);
}

}  // namespace

std::string cell_state_name(std::int8_t state) {
  static const char* const kNames[] = {"STARTING",  "READY",  "RUNNING", "DEGRADED",
                                       "SAFE_HOLD", "FAILED", "STOPPED"};
  if (state >= 0 && state < static_cast<int>(std::size(kNames))) return kNames[state];
  return "STATE_" + std::to_string(state);
}

std::string format_cycle(const CycleRecord& r) {
  std::string s = fmt::format("cycle {} {}", r.cycle_id, r.state ? cell_state_name(*r.state) : "?");
  if (r.error) {
    s += fmt::format(" err mean {:.2f} max {:.2f} score {:.2f} mm (n {})", 1e3 * r.error->mean_m,
                     1e3 * r.error->max_m, 1e3 * r.error->score_m, r.error->compared);
  } else {
    s += " err -";
  }
  if (r.recomputed) {
    s += fmt::format(" re {:.2f}/{:.2f}", 1e3 * r.recomputed->mean_m, 1e3 * r.recomputed->max_m);
  }
  if (r.coverage) {
    s += fmt::format(" cov {:.2f} ({}/{})", *r.coverage, r.observed_vertices, r.num_vertices);
  }
  if (std::isfinite(r.latency_ms)) s += fmt::format(" lat {:.1f} ms", r.latency_ms);
  if (r.twin_truth_mean_m || r.tracked_truth_mean_m) {
    s += " truth";
    if (r.twin_truth_mean_m) s += fmt::format(" twin {:.2f}", 1e3 * *r.twin_truth_mean_m);
    if (r.tracked_truth_mean_m) s += fmt::format(" tracked {:.2f}", 1e3 * *r.tracked_truth_mean_m);
    s += " mm";
  }
  if (r.cameras_total > 0) {
    s += fmt::format(" cams {}/{}", r.cameras_ok, r.cameras_total);
    for (const std::string& lost : r.cameras_lost) s += " " + lost;
  }
  s += ages("arms", r.arms) + ages("grippers", r.grippers) + drops(r.bus);
  if (r.real_time_factor) s += fmt::format(" rtf {:.2f}{}", *r.real_time_factor, r.clock_held ? " held" : "");
  if (!r.reason.empty()) s += " | " + r.reason;
  return s;
}

std::string format_state_change(const StateChange& c) {
  return fmt::format("state {} -> {} at cycle {}{}", c.from ? cell_state_name(*c.from) : "(none)",
                     cell_state_name(c.to), c.cycle_id, c.reason.empty() ? "" : ": " + c.reason);
}

std::string format_summary(const MonitorSummary& s, const drivers::BusCounters& c) {
  std::string out =
      fmt::format("summary: {} cycles ({}..{}), {} missing, {:.2f} cycles/s\n", s.cycles(),
                  s.first_id(), s.last_id(), s.missing_count(), s.rate_hz());
  if (s.restarts() > 0)
    out += fmt::format("  cell restarts: {} (ids above are of the last run)\n", s.restarts());
  const auto gaps = s.missing_ranges();
  if (!gaps.empty()) {
    out += "  missing cycle ids:";
    const std::size_t shown = std::min<std::size_t>(gaps.size(), 20);
    for (std::size_t i = 0; i < shown; ++i) {
      out += gaps[i].first == gaps[i].second ? fmt::format(" {}", gaps[i].first)
                                             : fmt::format(" {}-{}", gaps[i].first, gaps[i].second);
    }
    if (shown < gaps.size()) out += fmt::format(" (+{} more gaps)", gaps.size() - shown);
    out += "\n";
  }
  if (s.cycles_with_error() > 0) {
    const Percentiles m = s.mean_error_m(), sc = s.score_error_m();
    out += fmt::format("  error mean mm: p50 {:.2f} p90 {:.2f} p99 {:.2f} max {:.2f} ({} cycles)\n",
                       1e3 * m.p50, 1e3 * m.p90, 1e3 * m.p99, 1e3 * m.max, s.cycles_with_error());
    out += fmt::format("  error score mm: p50 {:.2f} p90 {:.2f} p99 {:.2f} max {:.2f}\n",
                       1e3 * sc.p50, 1e3 * sc.p90, 1e3 * sc.p99, 1e3 * sc.max);
  }
  if (s.cycles_with_clock() > 0) {
    const Percentiles f = s.real_time_factor();
    out += fmt::format("  simulation clock: real-time factor p50 {:.2f} max {:.2f} ({} cycles)\n", f.p50, f.max,
                       s.cycles_with_clock());
  }
  if (s.recomputed() > 0) {
    out += fmt::format("  recomputed error: {} cycles, {} disagree (worst {:.4f} mm)\n",
                       s.recomputed(), s.mismatches(), 1e3 * s.worst_mismatch_m());
  }
  out += fmt::format(
      "  messages: {} delivered, dropped {} undecodable, {} rejected, {} callback errors; "
      "{} for completed cycles\n",
      c.delivered, c.decode_failures, c.rejected, c.callback_errors, s.late_messages());
  out += fmt::format("  state changes: {}\n", s.state_changes().size());
  for (const StateChange& change : s.state_changes())
    out += "    " + format_state_change(change) + "\n";
  out += fmt::format("  calibrations: {}\n", s.calibrations().size());
  for (const CalibrationEvent& event : s.calibrations()) out += "    " + format_calibration(event) + "\n";
  out += fmt::format("  diagnoses: {}\n", s.diagnoses().size());
  for (const DiagnosisEvent& event : s.diagnoses()) out += "    " + format_diagnosis(event) + "\n";
  return out;
}

std::string format_diagnosis(const DiagnosisEvent& e) {
  std::string out = fmt::format("diagnosis {}: {}", e.diagnosis_id, e.verdict);
  if (!e.effect.empty()) out += fmt::format(" {}{}", e.verdict == "effect" ? "" : "closest ", e.effect);
  out += fmt::format(", {} ({} states, {:.1f} s)", e.adoption, e.states, e.seconds);
  if (std::isfinite(e.base_held_out_m) && std::isfinite(e.effect_held_out_m)) {
    out += fmt::format(", held-out state {:.1f} -> {:.1f} mm mean (base fit -> with the effect)", 1e3 * e.base_held_out_m,
                       1e3 * e.effect_held_out_m);
  }
  return out + ": " + e.reason;
}

std::string format_calibration(const CalibrationEvent& e) {
  std::string out = fmt::format("calibration {}: {} ({} states fitted, {:.1f} s)", e.calibration_id, e.verdict,
                                e.states_fitted, e.seconds);
  if (std::isfinite(e.held_out_before_m) && std::isfinite(e.held_out_after_m)) {
    out += fmt::format(", held-out state {:.1f} -> {:.1f} mm mean", 1e3 * e.held_out_before_m, 1e3 * e.held_out_after_m);
  }
  for (const std::string& p : e.parameters) out += "; " + p;
  return out + ": " + e.reason;
}

}  // namespace cell
