// Settled states of the held sheet (cell/learning/settled_state.h): when a window of tracked
// cycles counts as a settled state, what it averages, and how the store keeps states.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "cell/learning/settled_state.h"

using cell::learning::SettledObservation;
using cell::learning::SettledStateDetector;
using cell::learning::SettledStateStore;
using cell::learning::SettleOptions;
using twin::Vec3;

namespace {

constexpr double kHz = 10.0;
constexpr int kVertices = 200;

std::vector<Vec3> sheet_at(double z_m) {
  std::vector<Vec3> v;
  for (int i = 0; i < kVertices; ++i) v.emplace_back(0.01 * (i % 20), 0.01 * (i / 20), z_m);
  return v;
}

// Feeds cycles from t0 for `seconds`: the grasps where given, the sheet at `sheet` plus tracker
// noise of sigma per coordinate (and `drift_m_s` along z), all vertices seen. Returns the states.
struct Feed {
  SettledStateDetector detector{kVertices, 2, kHz};
  std::mt19937 rng{7};
  std::int64_t cycle = 0;
  double t = 0.0;
  std::vector<SettledObservation> run(double seconds, const std::vector<Vec3>& grasps, std::vector<char> engaged,
                                      const std::vector<Vec3>& sheet, double sigma_m, double drift_m_s = 0.0,
                                      const std::vector<std::uint8_t>* observed = nullptr) {
    std::normal_distribution<double> noise(0.0, sigma_m);
    std::vector<SettledObservation> out;
    const std::vector<std::uint8_t> all(kVertices, 1);
    for (int k = 0; k < static_cast<int>(std::lround(seconds * kHz)); ++k, ++cycle, t += 1.0 / kHz) {
      std::vector<Vec3> tracked = sheet;
      for (Vec3& p : tracked) p += Vec3(noise(rng), noise(rng), noise(rng) + drift_m_s * t);
      if (auto s = detector.add_cycle(t, cycle, grasps, engaged, tracked, observed ? *observed : all)) {
        out.push_back(*s);
      }
    }
    return out;
  }
};

const std::vector<Vec3> kGrasps = {Vec3(-0.4, 0.0, 1.0), Vec3(0.4, 0.0, 1.0)};

}  // namespace

TEST_CASE("a still sheet under still grasps gives a settled state every window after the grasps settle") {
  Feed feed;
  const auto states = feed.run(8.0, kGrasps, {1, 1}, sheet_at(0.6), 0.001);
  // 3 s for the grasps to count as still, then a 2 s window: states at about 5 s and 7 s.
  REQUIRE(states.size() == 2);
  const SettledObservation& s = states.front();
  CHECK(s.time_s == Approx(4.9).margin(0.11));
  CHECK(s.moved_at_s == 0.0);
  CHECK(s.cycles == 20);
  CHECK(s.coverage == 1.0);
  // The mean is the sheet to within the noise of a 20-cycle mean (1 mm / sqrt(20) per coordinate).
  double worst = 0.0;
  for (int i = 0; i < kVertices; ++i) worst = std::max(worst, (s.vertices_m[i] - sheet_at(0.6)[i]).norm());
  CHECK(worst < 0.0015);
  CHECK(s.cycle_noise_m == Approx(0.001).epsilon(0.15));
  CHECK(s.mean_noise_m == Approx(0.001 / std::sqrt(20.0)).epsilon(0.15));
  CHECK(s.grasp_positions_m == kGrasps);
}

TEST_CASE("a moving grasp, a release or a sheet still swinging is no settled state") {
  Feed feed;
  // The grasp moves 5 mm per cycle for 10 s: never still.
  for (int k = 0; k < 100; ++k) {
    auto grasps = kGrasps;
    grasps[0].z() += 0.005 * k;
    CHECK(feed.run(0.1, grasps, {1, 1}, sheet_at(0.6), 0.001).empty());
  }
  // A sheet creeping 5 mm/s is not settled, whatever the window.
  Feed creeping;
  CHECK(creeping.run(10.0, kGrasps, {1, 1}, sheet_at(0.6), 0.0005, 0.005).empty());
  // A release is a change of grasps even where the gripper stays: the wait starts again.
  Feed released;
  CHECK(released.run(4.5, kGrasps, {1, 1}, sheet_at(0.6), 0.001).empty());
  const auto after = released.run(5.2, kGrasps, {1, 0}, sheet_at(0.5), 0.001);
  REQUIRE(after.size() == 1);
  CHECK(after.front().moved_at_s == Approx(4.5).margin(0.11));
  CHECK(after.front().engaged == std::vector<char>{1, 0});
  CHECK(after.front().vertices_m[0].z() == Approx(0.5).margin(0.002));
}

TEST_CASE("a noisy tracker still settles, vertices seen in too few cycles are left out") {
  Feed noisy;
  // 8 mm per coordinate: the half-window means differ by several mm from the noise alone.
  CHECK(noisy.run(8.0, kGrasps, {1, 1}, sheet_at(0.6), 0.008).size() == 2);

  Feed partly;
  std::vector<std::uint8_t> observed(kVertices, 1);
  for (int i = 0; i < kVertices / 2; ++i) observed[i] = 0;
  const auto states = partly.run(6.0, kGrasps, {1, 1}, sheet_at(0.6), 0.001, 0.0, &observed);
  REQUIRE(states.size() == 1);
  CHECK(states.front().coverage == 0.5);
  CHECK_FALSE(states.front().vertices_m[0].allFinite());
  CHECK(states.front().vertices_m[kVertices - 1].allFinite());
  // Too little of the sheet seen: no state.
  SettleOptions options;
  options.min_coverage = 0.6;
  Feed strict{SettledStateDetector(kVertices, 2, kHz, options)};
  CHECK(strict.run(6.0, kGrasps, {1, 1}, sheet_at(0.6), 0.001, 0.0, &observed).empty());
}

TEST_CASE("bad detector arguments are refused with what was expected") {
  CHECK_THROWS_WITH(SettledStateDetector(0, 2, kHz), Catch::Contains("at least one vertex"));
  CHECK_THROWS_AS(SettledStateDetector(10, 2, 0.0), std::invalid_argument);
  SettledStateDetector d(10, 2, kHz);
  CHECK_THROWS_WITH(d.add_cycle(0.0, 0, {Vec3::Zero()}, {1, 1}, {}, {}), Catch::Contains("for 2 grasps"));
}

TEST_CASE("the store replaces a state of the same grasps, appends another and keeps at most its bound") {
  SettledStateStore store(3, 0.005);
  auto state = [](double z, double t, std::vector<char> engaged = {1, 1}) {
    SettledObservation s;
    s.grasp_positions_m = {Vec3(0, 0, z), Vec3(1, 0, 1)};
    s.engaged = std::move(engaged);
    s.time_s = t;
    s.moved_at_s = t - 5;
    return s;
  };
  store.add(state(1.0, 10));
  store.add(state(1.002, 12));  // same grasps (2 mm): replaces, keeps the earlier move time
  REQUIRE(store.states().size() == 1);
  CHECK(store.states()[0].time_s == 12);
  CHECK(store.states()[0].moved_at_s == 5);
  store.add(state(1.0, 20, {1, 0}));  // a release: another state
  store.add(state(1.1, 30, {1, 0}));
  store.add(state(1.2, 40, {1, 0}));
  REQUIRE(store.states().size() == 3);
  CHECK(store.states()[0].time_s == 20);  // the oldest went
  CHECK(store.states()[2].time_s == 40);
  CHECK(store.revision() == 5);
  CHECK(store.added() == 4);
  CHECK_THROWS_AS(SettledStateStore(0), std::invalid_argument);
}
