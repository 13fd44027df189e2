#include "cell/learning/settled_state.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cell::learning {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The median of |d| for a 3D vector d whose coordinates are independent N(0, sd^2) (the
// Maxwell distribution's median is 1.5382 sd).
constexpr double kMaxwellMedianPerSd = 1.5382;

}  // namespace

SettledStateDetector::SettledStateDetector(int vertex_count, int grasp_count, double cycle_hz, SettleOptions options)
    : vertex_count_(vertex_count), grasp_count_(grasp_count), options_(options) {
  if (vertex_count < 1 || grasp_count < 1) {
    throw std::invalid_argument(
        fmt::format("settled states: need at least one vertex and one grasp, got {} and {}", vertex_count, grasp_count));
  }
  if (!(cycle_hz > 0.0) || !(options.window_s > 0.0) || !(options.min_still_s >= 0.0) ||
      !(options.grasp_tolerance_m > 0.0) || !(options.max_drift_m > 0.0) ||
      !(options.min_observed_fraction > 0.0 && options.min_observed_fraction <= 1.0) ||
      !(options.min_coverage >= 0.0 && options.min_coverage <= 1.0)) {
    throw std::invalid_argument(
        "settled states: cycle rate, window, tolerances must be > 0 and fractions in (0, 1]");
  }
  // At least four cycles: two per half, so each half has a mean and a scatter.
  window_cycles_ = std::max(4, static_cast<int>(std::lround(options.window_s * cycle_hz)));
}

bool SettledStateDetector::grasps_changed(const std::vector<twin::Vec3>& grasp_positions_m,
                                          const std::vector<char>& engaged) const {
  if (!have_reference_) return true;
  for (int g = 0; g < grasp_count_; ++g) {
    if (engaged[g] != engaged_reference_[g]) return true;
    // A released grasp's gripper goes its own way; only the holding ones shape the sheet.
    if (engaged[g] && !((grasp_positions_m[g] - grasp_reference_m_[g]).norm() <= options_.grasp_tolerance_m)) {
      return true;
    }
  }
  return false;
}

std::optional<SettledObservation> SettledStateDetector::add_cycle(double time_s, std::int64_t cycle,
                                                                  const std::vector<twin::Vec3>& grasp_positions_m,
                                                                  const std::vector<char>& engaged,
                                                                  const std::vector<twin::Vec3>& tracked_m,
                                                                  const std::vector<std::uint8_t>& observed) {
  if (static_cast<int>(grasp_positions_m.size()) != grasp_count_ || static_cast<int>(engaged.size()) != grasp_count_) {
    throw std::invalid_argument(fmt::format("settled states: {} grasp positions and {} engaged flags for {} grasps",
                                            grasp_positions_m.size(), engaged.size(), grasp_count_));
  }
  if (grasps_changed(grasp_positions_m, engaged)) {
    grasp_reference_m_ = grasp_positions_m;
    engaged_reference_ = engaged;
    moved_at_s_ = time_s;
    have_reference_ = true;
    window_.clear();
    return std::nullopt;
  }
  const bool tracked = static_cast<int>(tracked_m.size()) == vertex_count_ &&
                       static_cast<int>(observed.size()) == vertex_count_;
  if (!tracked || time_s - moved_at_s_ < options_.min_still_s) return std::nullopt;
  window_.push_back(Frame{cycle, time_s, tracked_m, observed});
  if (static_cast<int>(window_.size()) < window_cycles_) return std::nullopt;
  std::optional<SettledObservation> state = settled();
  if (state) {
    window_.clear();
  } else {
    window_.erase(window_.begin());  // slide: the next cycle tries the window ending there
  }
  return state;
}

std::optional<SettledObservation> SettledStateDetector::settled() const {
  const int w = static_cast<int>(window_.size());
  const int half = w / 2;
  const int min_seen = std::max(2, static_cast<int>(std::ceil(options_.min_observed_fraction * w)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SettledObservation s;
  s.vertices_m.assign(static_cast<std::size_t>(vertex_count_), twin::Vec3::Constant(nan));
  std::vector<double> scatter, drift;
  for (int i = 0; i < vertex_count_; ++i) {
    twin::Vec3 sum[2] = {twin::Vec3::Zero(), twin::Vec3::Zero()};
    int count[2] = {0, 0};
    for (int k = 0; k < w; ++k) {
      const Frame& f = window_[static_cast<std::size_t>(k)];
      if (!f.observed[static_cast<std::size_t>(i)] || !f.tracked_m[static_cast<std::size_t>(i)].allFinite()) continue;
      const int h = k < half ? 0 : 1;
      sum[h] += f.tracked_m[static_cast<std::size_t>(i)];
      ++count[h];
    }
    const int seen = count[0] + count[1];
    if (seen < min_seen || count[0] == 0 || count[1] == 0) continue;
    const twin::Vec3 mean = (sum[0] + sum[1]) / seen;
    double squares = 0.0;
    for (int k = 0; k < w; ++k) {
      const Frame& f = window_[static_cast<std::size_t>(k)];
      if (!f.observed[static_cast<std::size_t>(i)] || !f.tracked_m[static_cast<std::size_t>(i)].allFinite()) continue;
      squares += (f.tracked_m[static_cast<std::size_t>(i)] - mean).squaredNorm();
    }
    s.vertices_m[static_cast<std::size_t>(i)] = mean;
    scatter.push_back(std::sqrt(squares / (3.0 * (seen - 1))));
    drift.push_back((sum[0] / count[0] - sum[1] / count[1]).norm());
  }
  const int kept = static_cast<int>(scatter.size());
  s.coverage = static_cast<double>(kept) / vertex_count_;
  if (kept == 0 || s.coverage < options_.min_coverage) return std::nullopt;
  s.cycle_noise_m = median(scatter);
  s.mean_noise_m = s.cycle_noise_m / std::sqrt(static_cast<double>(w));
  s.drift_m = median(drift);
  // What the scatter alone makes the distance between two half-window means: per coordinate
  // sd sqrt(1/h1 + 1/h2) with h1 + h2 = w, about 2 / sqrt(w).
  const double noise_drift_m = kMaxwellMedianPerSd * s.cycle_noise_m * 2.0 / std::sqrt(static_cast<double>(w));
  if (!(s.drift_m < std::max(options_.max_drift_m, 2.0 * noise_drift_m))) return std::nullopt;
  s.grasp_positions_m = grasp_reference_m_;
  s.engaged = engaged_reference_;
  s.cycles = w;
  s.first_cycle = window_.front().cycle;
  s.last_cycle = window_.back().cycle;
  s.time_s = window_.back().time_s;
  s.moved_at_s = moved_at_s_;
  return s;
}

SettledStateStore::SettledStateStore(int max_states, double same_grasp_tolerance_m)
    : max_states_(max_states), tolerance_m_(same_grasp_tolerance_m) {
  if (max_states < 1 || !(same_grasp_tolerance_m >= 0.0)) {
    throw std::invalid_argument(fmt::format("settled state store: max_states must be >= 1 (got {}) and the "
                                            "tolerance >= 0 m (got {})",
                                            max_states, same_grasp_tolerance_m));
  }
}

bool SettledStateStore::same_grasps(const SettledObservation& a, const SettledObservation& b) const {
  if (a.engaged != b.engaged || a.grasp_positions_m.size() != b.grasp_positions_m.size()) return false;
  for (std::size_t g = 0; g < a.engaged.size(); ++g) {
    if (a.engaged[g] && !((a.grasp_positions_m[g] - b.grasp_positions_m[g]).norm() <= tolerance_m_)) return false;
  }
  return true;
}

void SettledStateStore::add(SettledObservation state) {
  ++revision_;
  if (!states_.empty() && same_grasps(states_.back(), state)) {
    // The grasps last moved when the replaced state's did: keep its moved_at (the load's age).
    state.moved_at_s = std::min(state.moved_at_s, states_.back().moved_at_s);
    states_.back() = std::move(state);
    return;
  }
  states_.push_back(std::move(state));
  ++added_;
  if (static_cast<int>(states_.size()) > max_states_) states_.erase(states_.begin());
}

}  // namespace cell::learning
