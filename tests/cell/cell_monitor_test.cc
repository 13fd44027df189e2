// The terminal monitor's logic on memq://: per-cycle records from the cell's messages, the
// printed line, lost cameras and state changes, missing cycles, dropped malformed messages, a
// published error that disagrees with the recomputed one, and the fake world's truth.
#include "cell/cell_monitor.h"

#include <catch2/catch.hpp>
#include <chrono>
#include <random>
#include <vector>

#include "cell/monitor_format.h"
#include "drivers/lcm_channels.h"
#include "tests/cell/cycle_messages.h"

using cell::CellMonitor;
using cell::CycleRecord;
using testing_support::make_cycle;
using testing_support::publish_cycle;
namespace ch = drivers::channels;

namespace {

constexpr std::int64_t kStart_us = 1'800'000'000'000'000;
constexpr std::int64_t kPeriod_us = 100'000;  // 10 Hz

// A monitor on memq:// with a settable clock that keeps every record and state change.
struct Harness {
  drivers::LcmBus bus{"memq://"};
  std::int64_t clock_us = kStart_us;
  std::vector<CycleRecord> records;
  std::vector<cell::StateChange> changes;
  CellMonitor monitor{
      bus, cell::MonitorOptions{},
      cell::MonitorSinks{[this](const CycleRecord& r) { records.push_back(r); },
                         [this](const cell::StateChange& c) { changes.push_back(c); }, {}, {}},
      [this] { return clock_us; }};

  void dispatch() {
    while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
    }
  }
  // Publishes cycle `id` at its time and dispatches it.
  testing_support::CycleMessages cycle(std::int64_t id, std::mt19937& rng,
                                       const std::string& lost = "") {
    clock_us = kStart_us + id * kPeriod_us;
    auto c = make_cycle(id, clock_us, rng, 8, lost);
    REQUIRE(publish_cycle(bus, c));
    dispatch();
    return c;
  }
};

}  // namespace

TEST_CASE("one record per cycle with the published and recomputed error", "[monitor]") {
  Harness h;
  std::mt19937 rng(7);
  std::vector<testing_support::CycleMessages> sent;
  for (int id = 0; id < 5; ++id) sent.push_back(h.cycle(id, rng));
  REQUIRE(h.records.size() == 5);
  for (int id = 0; id < 5; ++id) {
    const CycleRecord& r = h.records[id];
    const auto& e = sent[id].error;
    CHECK(r.cycle_id == id);
    REQUIRE(r.state);
    CHECK(*r.state == prepreg_lcm::cell_state_t::STATE_RUNNING);
    REQUIRE(r.error);
    CHECK(r.error->mean_m == Approx(e.mean_m).epsilon(0));
    CHECK(r.error->compared == e.num_compared);
    REQUIRE(r.recomputed);
    CHECK(r.recomputed->compared == e.num_compared);
    CHECK(r.recomputed->mean_m == Approx(e.mean_m).margin(1e-7));
    CHECK(r.recomputed->max_m == Approx(e.max_m).margin(1e-7));
    CHECK(r.recomputed->score_m == Approx(e.score_m).margin(1e-7));
    CHECK(r.latency_ms == Approx(40.0));
    REQUIRE(r.coverage);
    CHECK(*r.coverage == Approx(sent[id].observed.coverage));
    CHECK(r.observed_vertices == e.num_compared);
    CHECK(r.num_vertices == 64);
    CHECK(r.cameras_ok == 3);
    CHECK(r.cameras_total == 3);
    REQUIRE(r.arms.size() == 2);
    CHECK(r.arms[0].name == "LEFT");
    CHECK(r.arms[0].age_ms == Approx(0.0));
  }
  const std::string line = cell::format_cycle(h.records[3]);
  CHECK_THAT(line, Catch::StartsWith("cycle 3 RUNNING err mean "));
  CHECK_THAT(line, Catch::Contains("lat 40.0 ms"));
  CHECK_THAT(line, Catch::Contains("cams 3/3"));
  CHECK_THAT(line, Catch::Contains("arms LEFT 0 RIGHT 0 ms"));
  CHECK_THAT(line, Catch::Contains("drops 0/0/0"));
  const auto& s = h.monitor.summary();
  CHECK(s.cycles() == 5);
  CHECK(s.missing_count() == 0);
  CHECK(s.rate_hz() == Approx(10.0));
  CHECK(s.recomputed() == 5);
  CHECK(s.mismatches() == 0);
}

TEST_CASE("a lost camera is named, state changes are reported", "[monitor]") {
  Harness h;
  std::mt19937 rng(8);
  h.cycle(0, rng);
  h.cycle(1, rng, "cam_right");
  h.cycle(2, rng);
  REQUIRE(h.records.size() == 3);
  CHECK(h.records[1].cameras_ok == 2);
  REQUIRE(h.records[1].cameras_lost == std::vector<std::string>{"cam_right (LOST)"});
  const std::string line = cell::format_cycle(h.records[1]);
  CHECK_THAT(line, Catch::Contains("DEGRADED"));
  CHECK_THAT(line, Catch::Contains("cams 2/3 cam_right (LOST)"));
  CHECK_THAT(line, Catch::EndsWith("| camera cam_right lost"));
  REQUIRE(h.changes.size() == 3);
  CHECK(!h.changes[0].from);
  CHECK(*h.changes[1].from == prepreg_lcm::cell_state_t::STATE_RUNNING);
  CHECK(h.changes[1].to == prepreg_lcm::cell_state_t::STATE_DEGRADED);
  CHECK(h.changes[1].cycle_id == 1);
  CHECK(cell::format_state_change(h.changes[2]) == "state DEGRADED -> RUNNING at cycle 2");

  // Camera status that stops arriving: silent after 2 s of monitor clock.
  h.clock_us += 3'000'000;
  auto c = make_cycle(30, h.clock_us, rng);
  c.cameras.pop_back();  // cam_right says nothing any more
  REQUIRE(publish_cycle(h.bus, c));
  h.dispatch();
  CHECK(h.records.back().cameras_lost == std::vector<std::string>{"cam_right (silent)"});
}

TEST_CASE("missing cycles, a lost CELL_STATE, late messages, percentiles", "[monitor]") {
  Harness h;
  std::mt19937 rng(9);
  std::vector<float> means;
  for (int id : {0, 1, 4}) means.push_back(h.cycle(id, rng).error.mean_m);
  // Cycle 5 without its CELL_STATE: completed by the first message of cycle 6.
  h.clock_us = kStart_us + 5 * kPeriod_us;
  auto c5 = make_cycle(5, h.clock_us, rng);
  REQUIRE(h.bus.publish(std::string(ch::kPredictionError), c5.error));
  h.dispatch();
  CHECK(h.records.size() == 3);
  means.push_back(c5.error.mean_m);
  means.push_back(h.cycle(6, rng).error.mean_m);
  REQUIRE(h.records.size() == 5);
  CHECK(h.records[3].cycle_id == 5);
  CHECK(!h.records[3].recomputed);  // no sheets for cycle 5
  CHECK(h.records[3].state);        // the latest known state stands in
  // A message of a finished cycle is late: counted, not used.
  REQUIRE(h.bus.publish(std::string(ch::kPredictionError), c5.error));
  h.dispatch();
  h.monitor.flush();
  const auto& s = h.monitor.summary();
  CHECK(s.cycles() == 5);
  CHECK(s.late_messages() == 1);
  REQUIRE(s.missing_ranges().size() == 1);
  CHECK(s.missing_ranges()[0] == std::pair<std::int64_t, std::int64_t>{2, 3});
  CHECK(s.missing_count() == 2);
  std::sort(means.begin(), means.end());
  CHECK(s.mean_error_m().max == Approx(means.back()).epsilon(1e-6));
  CHECK(s.mean_error_m().p50 == Approx(means[2]).epsilon(1e-6));  // nearest rank of 5
  const std::string text = cell::format_summary(s, h.bus.counters());
  CHECK_THAT(text, Catch::StartsWith("summary: 5 cycles (0..6), 2 missing"));
  CHECK_THAT(text, Catch::Contains("missing cycle ids: 2-3"));
}

TEST_CASE("malformed messages are dropped, counted and shown", "[monitor]") {
  Harness h;
  std::mt19937 rng(10);
  const std::uint8_t garbage[] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  REQUIRE(h.bus.publish_raw(std::string(ch::kPredictionError), garbage, sizeof garbage));
  auto bad = make_cycle(0, h.clock_us, rng);
  bad.observed.coverage = 2.0f;  // out of range: decodes, fails its check
  const auto bytes = testing_support::encode_message(bad.observed);
  REQUIRE(h.bus.publish_raw(std::string(ch::kSheetObserved), bytes.data(), bytes.size()));
  h.dispatch();
  CHECK(h.records.empty());
  const auto good = h.cycle(0, rng);
  REQUIRE(h.records.size() == 1);
  const CycleRecord& r = h.records[0];
  CHECK(r.bus.decode_failures == 1);
  CHECK(r.bus.rejected == 1);
  CHECK(*r.coverage == Approx(good.observed.coverage));  // the bad sheet never reached it
  CHECK_THAT(cell::format_cycle(r), Catch::EndsWith("drops 1/1/0"));
  CHECK_THAT(cell::format_summary(h.monitor.summary(), h.bus.counters()),
             Catch::Contains("dropped 1 undecodable, 1 rejected"));
}

TEST_CASE("a published error that disagrees with the sheets is a mismatch", "[monitor]") {
  Harness h;
  std::mt19937 rng(11);
  h.cycle(0, rng);
  h.clock_us += kPeriod_us;
  auto c = make_cycle(1, h.clock_us, rng);
  c.error.mean_m += 0.002f;  // 2 mm off what the sheets say (score kept consistent: it is checked)
  c.error.score_m += 0.002f;
  REQUIRE(publish_cycle(h.bus, c));
  h.dispatch();
  const auto& s = h.monitor.summary();
  CHECK(s.recomputed() == 2);
  CHECK(s.mismatches() == 1);
  CHECK(s.worst_mismatch_m() == Approx(0.002).margin(1e-6));
}

TEST_CASE("the fake world's true sheet is compared with twin and tracker", "[monitor]") {
  Harness h;
  std::mt19937 rng(12);
  auto c = make_cycle(0, h.clock_us, rng);
  prepreg_lcm::sheet_state_t truth = c.predicted;  // the twin is exact here
  truth.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  REQUIRE(h.bus.publish(std::string(ch::kSimTruth), truth));
  REQUIRE(publish_cycle(h.bus, c));
  h.dispatch();
  REQUIRE(h.records.size() == 1);
  const CycleRecord& r = h.records[0];
  REQUIRE(r.twin_truth_mean_m);
  CHECK(*r.twin_truth_mean_m == Approx(0.0).margin(1e-9));
  REQUIRE(r.tracked_truth_mean_m);
  // Tracked vertices carry ~4 mm noise per axis; nearest truth vertex is at most that far.
  CHECK(*r.tracked_truth_mean_m > 0.002);
  CHECK(*r.tracked_truth_mean_m <= r.error->mean_m + 1e-6);
  CHECK_THAT(cell::format_cycle(r), Catch::Contains("truth twin 0.00 tracked"));
}

TEST_CASE("a cell restart starts a new run of cycle ids", "[monitor]") {
  Harness h;
  std::mt19937 rng(13);
  for (int id : {0, 1, 3}) h.cycle(id, rng);
  prepreg_lcm::cell_state_t starting{};
  starting.utime = h.clock_us;
  starting.cycle_id = -1;
  starting.state = prepreg_lcm::cell_state_t::STATE_STARTING;
  starting.reason = "start-up";
  REQUIRE(h.bus.publish(std::string(ch::kCellState), starting));
  h.dispatch();
  for (int id : {0, 1}) h.cycle(id, rng);  // without the restart these would be "late"
  const auto& s = h.monitor.summary();
  CHECK(h.records.size() == 5);
  CHECK(s.cycles() == 5);
  CHECK(s.restarts() == 1);
  CHECK(s.late_messages() == 0);
  CHECK(s.missing_count() == 1);  // cycle 2 of the first run
  CHECK(s.first_id() == 0);
  CHECK(s.last_id() == 1);
  CHECK_THAT(cell::format_summary(s, h.bus.counters()), Catch::Contains("cell restarts: 1"));
}

TEST_CASE("calibration events are shown as they come and listed in the summary, a malformed one is dropped",
          "[monitor]") {
  Harness h;
  std::vector<cell::CalibrationEvent> seen;
  drivers::LcmBus bus{"memq://"};
  cell::MonitorSinks sinks;
  sinks.calibration = [&](const cell::CalibrationEvent& e) { seen.push_back(e); };
  CellMonitor monitor(bus, cell::MonitorOptions{}, sinks);
  prepreg_lcm::calibration_t m{};
  m.utime = kStart_us;
  m.calibration_id = 2;
  m.verdict = "refused";
  m.reason = "no better on the held-out state";
  m.num_parameters = 1;
  m.parameter_names = {"bending_Nm"};
  m.values = {6e-3};
  m.lower95 = {4e-3};
  m.upper95 = {9e-3};
  m.determined = {true};
  m.held_out_error_before_m = 0.0124;
  m.held_out_error_after_m = 0.0145;
  m.states_fitted = 3;
  m.states_held_out = 1;
  m.simulations = 15;
  m.seconds = 102.0;
  REQUIRE(bus.publish(std::string(ch::kCellCalibration), m));
  prepreg_lcm::calibration_t bad = m;
  bad.values = {1e-2};  // outside its own interval: decodes, fails its check, never shown
  const auto bytes = testing_support::encode_message(bad);
  REQUIRE(bus.publish_raw(std::string(ch::kCellCalibration), bytes.data(), bytes.size()));
  while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
  }
  REQUIRE(seen.size() == 1);
  CHECK(cell::format_calibration(seen[0]) ==
        "calibration 2: refused (3 states fitted, 102.0 s), held-out state 12.4 -> 14.5 mm mean; bending_Nm 0.006 "
        "[0.004, 0.009]: no better on the held-out state");
  CHECK_THAT(cell::format_summary(monitor.summary(), bus.counters()), Catch::Contains("calibrations: 1\n    calibration 2"));
  CHECK(bus.counters().rejected == 1);
}

TEST_CASE("diagnosis events are shown as they come and listed in the summary, a malformed one is dropped",
          "[monitor]") {
  Harness h;
  std::vector<cell::DiagnosisEvent> seen;
  drivers::LcmBus bus{"memq://"};
  cell::MonitorSinks sinks;
  sinks.diagnosis = [&](const cell::DiagnosisEvent& e) { seen.push_back(e); };
  CellMonitor monitor(bus, cell::MonitorOptions{}, sinks);
  prepreg_lcm::diagnosis_t m{};
  m.utime = kStart_us;
  m.diagnosis_id = 1;
  m.verdict = "effect";
  m.effect = "clamp_grip";
  m.adoption = "refused";
  m.reason = "clamp_grip named; no better on the held-out state";
  m.noise_sigma_m = 0.002;
  m.base_fitted_mean_m = 0.009;
  m.base_held_out_mean_m = 0.0121;
  m.effect_fitted_mean_m = 0.005;
  m.effect_held_out_mean_m = 0.0063;
  m.num_parameters = 1;
  m.parameter_names = {"clamp_grip_stiffness_N_m"};
  m.values = {40.0};
  m.lower95 = {30.0};
  m.upper95 = {55.0};
  m.held_out_error_before_m = 0.0124;
  m.held_out_error_after_m = 0.0119;
  m.states = 4;
  m.seconds = 310.2;
  REQUIRE(bus.publish(std::string(ch::kCellDiagnosis), m));
  prepreg_lcm::diagnosis_t bad = m;
  bad.verdict = "none";
  bad.adoption = "adopted";  // nothing named cannot be adopted: decodes, fails its check, never shown
  const auto bytes = testing_support::encode_message(bad);
  REQUIRE(bus.publish_raw(std::string(ch::kCellDiagnosis), bytes.data(), bytes.size()));
  while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
  }
  REQUIRE(seen.size() == 1);
  CHECK(cell::format_diagnosis(seen[0]) ==
        "diagnosis 1: effect clamp_grip, refused (4 states, 310.2 s), held-out state 12.1 -> 6.3 mm mean (base fit -> "
        "with the effect): clamp_grip named; no better on the held-out state");
  CHECK_THAT(cell::format_summary(monitor.summary(), bus.counters()), Catch::Contains("diagnoses: 1\n    diagnosis 1"));
  CHECK(bus.counters().rejected == 1);
}
