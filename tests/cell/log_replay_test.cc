// Replay of lcm-logger logs: a log written here with LCM's LogFile API (as lcm-logger writes it)
// replays into the monitor with the logged times, and the error recomputed from the logged
// sheets reproduces the logged PREDICTION_ERROR; a log whose error is wrong is caught; the
// replay_cell_log tool does the same end to end.
#include "cell/log_replay.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>
#include <random>
#include <stdexcept>
#include <string>

#include "cell/cell_monitor.h"
#include "tests/cell/cycle_messages.h"
#include "tests/support/run_command.h"
#include "tests/support/temp_dir.h"

namespace {

constexpr std::int64_t kLogStart_us = 1'800'000'000'000'000;

// Writes `cycles` cycles at 20 Hz, the messages of a cycle 1 ms apart; cycle `wrong` (if >= 0)
// logs a max error 3 mm larger than its sheets give. `simulated`: a run on the fake world's
// clock at half real time: each cycle starts with a SIM_CLOCK at its simulated time, and the
// logger's (wall) timestamps are twice as far apart.
void write_log(const std::string& path, int cycles, int wrong = -1, bool simulated = false) {
  lcm::LogFile log(path, "w");
  REQUIRE(log.good());
  std::mt19937 rng(21);
  std::int64_t event = 0;
  for (int id = 0; id < cycles; ++id) {
    const std::int64_t t = kLogStart_us + id * 50'000;
    if (simulated) {
      prepreg_lcm::sim_clock_t clock{};
      clock.utime = t;
      clock.sim_us = t - kLogStart_us;
      clock.real_time_factor = 0.5;
      std::vector<std::uint8_t> bytes(static_cast<std::size_t>(clock.getEncodedSize()));
      REQUIRE(clock.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == static_cast<int>(bytes.size()));
      lcm::LogEvent e;
      e.eventnum = event++;
      e.timestamp = kLogStart_us + 2 * (t - kLogStart_us);
      e.channel = "SIM_CLOCK";
      e.datalen = static_cast<int32_t>(bytes.size());
      e.data = bytes.data();
      REQUIRE(log.writeEvent(&e) == 0);
    }
    auto c = testing_support::make_cycle(id, t, rng, 10, id == 4 ? "cam_left" : "");
    if (id == wrong) {  // consistent in itself (score is checked on receipt), wrong for the sheets
      c.error.max_m += 0.003f;
      c.error.score_m += 0.0015f;
    }
    std::int64_t offset = 0;
    for (auto& m : testing_support::encode_cycle(c)) {
      lcm::LogEvent e;
      e.eventnum = event++;
      e.timestamp = simulated ? kLogStart_us + 2 * (t - kLogStart_us) + 2000 * offset++ : t + 1000 * offset++;
      e.channel = m.channel;
      e.datalen = static_cast<int32_t>(m.bytes.size());
      e.data = m.bytes.data();
      REQUIRE(log.writeEvent(&e) == 0);
    }
  }
}

struct Replayed {
  std::vector<cell::CycleRecord> records;
  cell::MonitorSummary summary;
  cell::ReplayStats stats;
};

Replayed replay(const std::string& path) {
  drivers::LcmBus bus("memq://");
  std::int64_t clock_us = 0;
  Replayed out;
  cell::CellMonitor monitor(bus, cell::MonitorOptions{},
                            {[&](const cell::CycleRecord& r) { out.records.push_back(r); }, {}, {}, {}},
                            [&] { return clock_us; });
  out.stats = cell::replay_log(path, bus, clock_us, cell::ReplayOptions{});
  monitor.flush();
  out.summary = monitor.summary();
  return out;
}

}  // namespace

TEST_CASE("replay: a logged run reproduces the logged errors at the logged times", "[monitor]") {
  testing_support::TempDir dir("replay_log");
  const std::string path = (dir / "run.lcmlog").string();
  write_log(path, 12);
  const Replayed r = replay(path);
  CHECK(r.stats.events == 12 * 9);  // 9 messages per cycle
  CHECK(r.stats.last_utime - r.stats.first_utime == 11 * 50'000 + 8'000);
  REQUIRE(r.records.size() == 12);
  for (const auto& rec : r.records) {
    REQUIRE(rec.error);
    REQUIRE(rec.recomputed);
    CHECK(rec.recomputed->compared == rec.error->compared);
    CHECK(rec.recomputed->mean_m == Approx(rec.error->mean_m).margin(1e-7));
    CHECK(rec.recomputed->max_m == Approx(rec.error->max_m).margin(1e-7));
    // IIWA_STATUS_LEFT was logged 2 ms before CELL_STATE, which completes the record.
    REQUIRE(rec.arms.size() == 2);
    CHECK(rec.arms[0].age_ms == Approx(2.0));
  }
  CHECK(r.records[4].cameras_lost == std::vector<std::string>{"cam_left (LOST)"});
  CHECK(r.summary.mismatches() == 0);
  CHECK(r.summary.rate_hz() == Approx(20.0));
  // RUNNING, DEGRADED at cycle 4 (cam_left lost), RUNNING again at 5.
  REQUIRE(r.summary.state_changes().size() == 3);
  CHECK(r.summary.state_changes()[1].cycle_id == 4);
  CHECK(r.summary.state_changes()[1].seen_utime ==
        kLogStart_us + 4 * 50'000 + 8'000);  // its CELL_STATE
}

TEST_CASE("replay: a run on the simulation clock replays on its SIM_CLOCK, not the logger's wall", "[monitor]") {
  testing_support::TempDir dir("replay_log");
  const std::string path = (dir / "sim.lcmlog").string();
  write_log(path, 12, -1, /*simulated=*/true);
  const Replayed r = replay(path);
  REQUIRE(r.records.size() == 12);
  CHECK(r.summary.rate_hz() == Approx(20.0));  // 20 Hz of simulated time (10 Hz on the logger's wall)
  REQUIRE(r.records.back().real_time_factor);
  CHECK(*r.records.back().real_time_factor == 0.5);
  CHECK(r.summary.cycles_with_clock() == 12);
  // Each cycle's messages fall at its SIM_CLOCK's time: its arm status is as old as it is then.
  CHECK(r.records.back().arms.at(0).age_ms == Approx(0.0));
}

TEST_CASE("replay: a log whose error disagrees with its sheets is caught", "[monitor]") {
  testing_support::TempDir dir("replay_wrong");
  const std::string path = (dir / "wrong.lcmlog").string();
  write_log(path, 8, 5);
  const Replayed r = replay(path);
  CHECK(r.summary.recomputed() == 8);
  CHECK(r.summary.mismatches() == 1);
  CHECK(r.summary.worst_mismatch_m() == Approx(0.003).margin(1e-6));
}

TEST_CASE("replay: a file that is not an LCM log is refused with its name", "[monitor]") {
  testing_support::TempDir dir("replay_bad");
  const std::string path = (dir / "notes.txt").string();
  std::ofstream(path) << "not an LCM log\n";
  drivers::LcmBus bus("memq://");
  std::int64_t clock_us = 0;
  CHECK_THROWS_WITH(cell::replay_log(path, bus, clock_us, {}),
                    Catch::Contains(path) && Catch::Contains("no events"));
  CHECK_THROWS_WITH(cell::replay_log(path + ".missing", bus, clock_us, {}),
                    Catch::Contains("cannot open"));
}

TEST_CASE("replay: the replay_cell_log tool prints the cycles and exits by agreement",
          "[monitor]") {
  testing_support::TempDir dir("replay_tool");
  const std::string good = (dir / "good.lcmlog").string(), bad = (dir / "bad.lcmlog").string();
  write_log(good, 6);
  write_log(bad, 6, 2);
  std::string out;
  CHECK(testing_support::run_command(std::string(REPLAY_CELL_LOG_EXE) + " " + good + " --every 2", out) == 0);
  CHECK_THAT(out, Catch::Contains("cycle 0 RUNNING err mean"));
  CHECK_THAT(out, Catch::Contains("cycle 4 DEGRADED"));
  CHECK_THAT(out, !Catch::Contains("cycle 1 "));  // --every 2
  CHECK_THAT(out, Catch::Contains("summary: 6 cycles (0..5), 0 missing"));
  CHECK_THAT(out, Catch::Contains("recomputed error: 6 cycles, 0 disagree"));
  out.clear();
  CHECK(testing_support::run_command(std::string(REPLAY_CELL_LOG_EXE) + " " + bad, out) == 2);
  CHECK_THAT(out, Catch::Contains("recomputed error: 6 cycles, 1 disagree"));
  out.clear();
  CHECK(testing_support::run_command(std::string(REPLAY_CELL_LOG_EXE) + " " + good + ".missing", out) == 1);
  CHECK_THAT(out, Catch::Contains("cannot open"));
}
