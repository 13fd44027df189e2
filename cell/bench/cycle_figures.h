#pragma once
// The cell benchmark's figures: per-cycle times of a phase gathered from CycleReports and printed
// as one "figure:" line (rate, latency, stage times as median / p99), the verdict against the
// issue's target (rate, latency p99 <= 50 ms), the process RSS sampled over the run and the
// machine's load average (the 2 cores are shared, so every figure says how busy they were).
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "cell/cell_controller.h"

namespace cell_bench {

inline constexpr double kLatencyTargetP99Ms = 50.0;  // the target, ms

class CycleFigures {
 public:
  void add(const cell::CycleReport& r);
  // A tracked cycle's tracker figures (the cell's last_track()): stage times, points, iterations.
  void add_tracker_cycle(const tracking::TrackResult& r);
  void count_sweep() { ++sweeps_; }
  int cycles() const { return cycles_; }
  double rate_hz() const;  // cycles per second between the first and the last added cycle
  std::string line(const std::string& label, const std::string& phase) const;
  // "target: ... met" or "target: ... NOT met by ...; dominant stage ..." (the twin's step
  // holds a cycle back only when the cell runs it in lockstep).
  std::string verdict(double target_hz, bool lockstep) const;
  // "tracker stages (median ms): fusion .. | registration iterations .. | resampled points .."
  // (calibration as p99: it runs every n-th cycle only).
  std::string tracker_stages_line() const;

 private:
  int cycles_ = 0, tracked_ = 0, sweeps_ = 0, twin_substeps_ = 0, max_twin_substeps_ = 0;
  std::chrono::steady_clock::time_point first_, last_;
  std::vector<double> latency_ms_, frame_age_ms_, tracker_ms_, twin_ms_, cycle_ms_;
  std::map<std::string, int> states_;
  struct TrackerCycle {
    tracking::StageTimes times;
    int resampled_points = 0, registration_iterations = 0;
    bool warm = false, restarted = false;
  };
  std::vector<TrackerCycle> tracker_cycles_;
};

// The p-quantile (0..1, nearest rank) of v; 0 when empty.
double percentile(std::vector<double> v, double p);

// Resident set size of this process (/proc/self/status VmRSS), MB; -1 if unreadable.
double rss_mb();
// "load average 2.53 2.42 3.70 (1/5/15 min, N cores)" from /proc/loadavg.
std::string load_average_line();

// Prints "memory: t=.. s rss=.. MB" at the first poll after warm-up and every period after;
// finish() adds the last sample and the "memory growth" line: last - first, and the rate over
// the run's second half (from the first sample at or after half-time). The cell's resident set
// grows by tens of MB in its first seconds (buffers and factor objects reaching their working
// sizes) and then stays flat, so a rate over the whole of a short run says nothing about a
// leak; the second half's does.
class MemorySampler {
 public:
  MemorySampler(double every_s, double first_at_s) : every_s_(every_s), next_s_(first_at_s) {}
  void poll(double t_s);
  void finish(double t_s);

 private:
  struct Sample {
    double t_s, mb;
  };
  void sample(double t_s);
  double every_s_, next_s_;
  std::vector<Sample> samples_;
};

}  // namespace cell_bench
