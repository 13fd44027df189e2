// Session totals of the monitor.
#include "cell/monitor_summary.h"

#include <algorithm>
#include <cmath>

namespace cell {

void MonitorSummary::add_cycle(const CycleRecord& r) {
  if (cycles() == 0) first_seen_utime_ = r.seen_utime;
  last_seen_utime_ = r.seen_utime;
  ids_.insert(r.cycle_id);
  last_bus_ = r.bus;
  if (r.real_time_factor) real_time_factors_.push_back(*r.real_time_factor);
  if (r.error) {
    means_m_.push_back(r.error->mean_m);
    scores_m_.push_back(r.error->score_m);
  }
  if (r.error && r.recomputed) {
    ++recomputed_;
    const double diff = std::max({std::abs(r.error->mean_m - r.recomputed->mean_m),
                                  std::abs(r.error->max_m - r.recomputed->max_m),
                                  std::abs(r.error->score_m - r.recomputed->score_m)});
    worst_mismatch_m_ = std::max(worst_mismatch_m_, diff);
    if (diff > kMismatchTolerance_m || r.error->compared != r.recomputed->compared) ++mismatches_;
  }
}

std::vector<std::pair<std::int64_t, std::int64_t>> MonitorSummary::missing_ranges() const {
  std::vector<std::pair<std::int64_t, std::int64_t>> gaps;
  std::int64_t previous = -1;
  bool first = true;
  for (std::int64_t id : ids_) {
    if (!first && id > previous + 1) gaps.emplace_back(previous + 1, id - 1);
    previous = id;
    first = false;
  }
  return gaps;
}

void MonitorSummary::start_new_run() {
  prior_cycles_ += static_cast<int>(ids_.size());
  prior_missing_ = missing_count();  // before ids_ is cleared: includes this run's gaps
  ids_.clear();
  ++restarts_;
}

std::int64_t MonitorSummary::missing_count() const {
  std::int64_t n = prior_missing_;
  for (const auto& [a, b] : missing_ranges()) n += b - a + 1;
  return n;
}

double MonitorSummary::rate_hz() const {
  if (cycles() < 2 || last_seen_utime_ <= first_seen_utime_) return 0.0;
  return (static_cast<double>(cycles()) - 1.0) * 1e6 /
         static_cast<double>(last_seen_utime_ - first_seen_utime_);
}

Percentiles MonitorSummary::percentiles(std::vector<double> v) {
  Percentiles p;
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  // Nearest rank: the smallest value with at least q of the values at or below it.
  auto at = [&](double q) {
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
  };
  p.p50 = at(0.50);
  p.p90 = at(0.90);
  p.p99 = at(0.99);
  p.max = v.back();
  return p;
}

}  // namespace cell
