#include "cell/bench/cycle_figures.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

namespace cell_bench {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::max(0.0, std::ceil(p * static_cast<double>(v.size())) - 1.0));
  return v[std::min(v.size() - 1, rank)];
}

void CycleFigures::add(const cell::CycleReport& r) {
  const auto now = std::chrono::steady_clock::now();
  if (cycles_ == 0) first_ = now;
  last_ = now;
  ++cycles_;
  ++states_[cell::to_string(r.state)];
  if (r.tracked) ++tracked_;
  if (r.latency_ms >= 0) latency_ms_.push_back(r.latency_ms);
  if (r.latency_ms >= 0 && r.frame_age_ms >= 0) frame_age_ms_.push_back(r.frame_age_ms);
  if (r.frames > 0) tracker_ms_.push_back(r.tracker_ms);
  if (r.twin_stepped) {
    twin_ms_.push_back(r.twin_step_ms);
    twin_substeps_ += r.twin_substeps;
    max_twin_substeps_ = std::max(max_twin_substeps_, r.twin_substeps);
  }
  cycle_ms_.push_back(r.cycle_ms);
}

double CycleFigures::rate_hz() const {
  const double s = std::chrono::duration<double>(last_ - first_).count();
  return cycles_ > 1 && s > 0 ? (cycles_ - 1) / s : 0.0;
}

std::string CycleFigures::line(const std::string& label, const std::string& phase) const {
  std::string states;
  for (const auto& [state, n] : states_) states += fmt::format("{}{} {}", states.empty() ? "" : ", ", state, n);
  return fmt::format(
      "figure: {} ({}): rate {:.1f} Hz latency median {:.1f} ms p99 {:.1f} ms (frame age at read median {:.1f} p99 {:.1f})"
      " | tracker median {:.1f} p99 {:.1f} ms"
      " | twin step median {:.1f} p99 {:.1f} ms (sub-steps mean {:.2f} max {}) | cycle median {:.1f} p99 {:.1f} ms | {} cycles, {} tracked,"
      " {} twin steps, {} latencies, {} goal sweeps, states: {} | {}",
      label, phase, rate_hz(), percentile(latency_ms_, 0.5), percentile(latency_ms_, 0.99),
      percentile(frame_age_ms_, 0.5), percentile(frame_age_ms_, 0.99),
      percentile(tracker_ms_, 0.5), percentile(tracker_ms_, 0.99), percentile(twin_ms_, 0.5),
      percentile(twin_ms_, 0.99),
      twin_ms_.empty() ? 0.0 : static_cast<double>(twin_substeps_) / static_cast<double>(twin_ms_.size()),
      max_twin_substeps_, percentile(cycle_ms_, 0.5), percentile(cycle_ms_, 0.99), cycles_, tracked_,
      twin_ms_.size(), latency_ms_.size(), sweeps_, states, load_average_line());
}

void CycleFigures::add_tracker_cycle(const tracking::TrackResult& r) {
  tracker_cycles_.push_back({r.times, r.resampled_points, r.registration_iterations, r.registration_warm,
                             r.registration_restarted});
}

std::string CycleFigures::tracker_stages_line() const {
  // One figure of every tracked cycle.
  auto column = [&](auto field) {
    std::vector<double> v;
    for (const TrackerCycle& c : tracker_cycles_) v.push_back(field(c));
    return v;
  };
  std::string s = "tracker stages (median ms):";
  const std::pair<const char*, double tracking::StageTimes::*> stages[] = {
      {"fusion", &tracking::StageTimes::fusion_ms},           {"segmentation", &tracking::StageTimes::segmentation_ms},
      {"resample+index", &tracking::StageTimes::resample_ms}, {"registration", &tracking::StageTimes::registration_ms},
      {"coverage", &tracking::StageTimes::coverage_ms},       {"prediction_error", &tracking::StageTimes::prediction_error_ms}};
  for (const auto& [name, member] : stages) {
    s += fmt::format(" {} {:.1f}", name, percentile(column([member = member](const TrackerCycle& t) { return t.times.*member; }), 0.5));
  }
  // Calibration runs every n-th cycle only: its p99.
  s += fmt::format(" calibration p99 {:.1f}",
                   percentile(column([](const TrackerCycle& t) { return t.times.calibration_ms; }), 0.99));
  int warm = 0, restarted = 0;
  for (const TrackerCycle& c : tracker_cycles_) warm += c.warm, restarted += c.restarted;
  s += fmt::format(" | registration iterations {:.0f} (p99 {:.0f}), {} of {} warm, {} restarted | resampled points {:.0f}",
                   percentile(column([](const TrackerCycle& t) { return double(t.registration_iterations); }), 0.5),
                   percentile(column([](const TrackerCycle& t) { return double(t.registration_iterations); }), 0.99),
                   warm, tracker_cycles_.size(), restarted,
                   percentile(column([](const TrackerCycle& t) { return double(t.resampled_points); }), 0.5));
  return s;
}

std::string CycleFigures::verdict(double target_hz, bool lockstep) const {
  const double rate = rate_hz(), p99 = percentile(latency_ms_, 0.99);
  // A rate within 2% of the target counts as met: the pacing loop starts late cycles at once,
  // so a cell that keeps up runs at the target minus timer jitter.
  const bool rate_ok = rate >= 0.98 * target_hz, latency_ok = !latency_ms_.empty() && p99 <= kLatencyTargetP99Ms;
  std::string s = fmt::format("target {:.0f} Hz, latency p99 <= {:.0f} ms: ", target_hz, kLatencyTargetP99Ms);
  if (rate_ok && latency_ok) return s + "met";
  s += "NOT met:";
  if (!rate_ok) s += fmt::format(" rate {:.1f} Hz is {:.1f} Hz short;", rate, target_hz - rate);
  if (latency_ms_.empty()) s += " no latency measured (no frame led to a published error);";
  else if (!latency_ok) s += fmt::format(" latency p99 {:.1f} ms is {:.1f} ms over;", p99, p99 - kLatencyTargetP99Ms);
  const double tracker = percentile(tracker_ms_, 0.5), twin = percentile(twin_ms_, 0.5);
  const double age = percentile(frame_age_ms_, 0.99);
  // The twin holds a cycle back only in lockstep; otherwise it steps at its own pace.
  const bool twin_holds = lockstep && twin > tracker;
  return s + fmt::format(" dominant stage: {} (medians tracker {:.1f} ms, twin step {:.1f} ms{}, cycle budget {:.1f} ms;"
                         " frame age at read p99 {:.1f} ms)",
                         twin_holds ? "twin" : "tracker", tracker, twin, lockstep ? "" : " at its own pace",
                         1e3 / target_hz, age);
}

double rss_mb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) {
      std::istringstream fields(line.substr(6));
      double kb = 0;
      if (fields >> kb) return kb / 1024.0;
    }
  }
  return -1.0;
}

std::string load_average_line() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "load average unavailable";
  return fmt::format("load average {:.2f} {:.2f} {:.2f} (1/5/15 min, {} cores)", a, b, c,
                     std::thread::hardware_concurrency());
}

void MemorySampler::sample(double t_s) {
  const double mb = rss_mb();
  samples_.push_back({t_s, mb});
  fmt::print("memory: t={:.0f} s rss={:.1f} MB\n", t_s, mb);
  std::fflush(stdout);
}

void MemorySampler::poll(double t_s) {
  if (t_s < next_s_) return;
  sample(t_s);
  while (next_s_ <= t_s) next_s_ += every_s_;
}

void MemorySampler::finish(double t_s) {
  sample(t_s);
  const Sample& first = samples_.front();
  const Sample& last = samples_.back();
  const double half_s = 0.5 * (first.t_s + last.t_s);
  const auto mid = std::find_if(samples_.begin(), samples_.end(), [&](const Sample& s) { return s.t_s >= half_s; });
  std::string second_half = "; too few samples for the second half's rate (shorten --memory-every-s)";
  if (mid != samples_.end() && last.t_s - mid->t_s > 0.0) {
    second_half = fmt::format("; second half, t={:.0f} s to {:.0f} s: {:+.1f} MB, {:+.2f} MB/min", mid->t_s, last.t_s,
                              last.mb - mid->mb, 60.0 * (last.mb - mid->mb) / (last.t_s - mid->t_s));
  }
  fmt::print("memory growth: {:+.1f} MB from t={:.0f} s ({:.1f} MB) to t={:.0f} s ({:.1f} MB){}\n", last.mb - first.mb,
             first.t_s, first.mb, last.t_s, last.mb, second_half);
}

}  // namespace cell_bench
