// The process's clock and the cell's side of the simulation clock: while a SimClockClient is
// alive every reader of time in the process (host_clock_us, utime_now) follows SIM_CLOCK; a
// lockstep client's advance_to holds the world with SIM_CLOCK_HOLD and returns when the clock
// has got there, or when it falls silent; the messages' checks.
#include <catch2/catch.hpp>

#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>

#include "common/process_clock.h"
#include "drivers/lcm_channels.h"
#include "drivers/sim_clock_client.h"

namespace {

prepreg_lcm::sim_clock_t clock_at(std::int64_t utime) {
  prepreg_lcm::sim_clock_t m{};
  m.utime = utime;
  m.sim_us = utime - 1'000'000'000;
  m.real_time_factor = 0.5;
  m.state = prepreg_lcm::sim_clock_t::STATE_RUNNING;
  return m;
}

}  // namespace

TEST_CASE("the process runs on simulation time while one is alive, and on the wall again after", "[sim_clock]") {
  const std::int64_t wall_before = drivers::utime_now();
  REQUIRE_FALSE(prepreg::simulated_time_active());
  {
    prepreg::SimulatedTime time;
    CHECK(prepreg::simulated_time_active());
    CHECK(drivers::utime_now() == 0);
    time.set_us(1'700'000'000'000'000);
    CHECK(drivers::utime_now() == 1'700'000'000'000'000);
    CHECK(prepreg::process_steady_us() == 1'700'000'000'000'000);
    time.set_us(1'600'000'000'000'000);  // never back
    CHECK(drivers::utime_now() == 1'700'000'000'000'000);
    CHECK_THROWS_AS(prepreg::SimulatedTime(), std::logic_error);  // one clock per process
  }
  CHECK_FALSE(prepreg::simulated_time_active());
  CHECK(drivers::utime_now() >= wall_before);
}

TEST_CASE("clock source names", "[sim_clock]") {
  CHECK(drivers::clock_source_from_name("sim") == drivers::ClockSource::kSim);
  CHECK(drivers::clock_source_from_name("wall") == drivers::ClockSource::kWall);
  CHECK_FALSE(drivers::clock_source_from_name("Sim"));
  CHECK(std::string(drivers::to_string(drivers::ClockSource::kSim)) == "sim");
}

TEST_CASE("a lockstep client holds the clock and follows it", "[sim_clock]") {
  drivers::LcmBus bus("memq://");
  std::vector<prepreg_lcm::sim_clock_hold_t> holds;
  bus.subscribe<prepreg_lcm::sim_clock_hold_t>(std::string(drivers::channels::kSimClockHold),
                                               [&](const prepreg_lcm::sim_clock_hold_t& m) { holds.push_back(m); });
  // A stand-in for the world: on each hold it runs the clock to the hold (memq delivers at once,
  // on the handling thread, so the answer comes within the client's own handle_for).
  const std::int64_t t0 = 1'000'000'000;
  bus.subscribe<prepreg_lcm::sim_clock_hold_t>(std::string(drivers::channels::kSimClockHold),
                                               [&](const prepreg_lcm::sim_clock_hold_t& m) {
                                                 if (!m.leaving) bus.publish(std::string(drivers::channels::kSimClock), clock_at(m.until_utime));
                                               });
  {
    drivers::SimClockClient client(bus, "cell_controller");
    CHECK(client.now_us() == 0);
    REQUIRE(client.advance_to(t0, 5.0));
    CHECK(client.now_us() == t0);
    CHECK(drivers::utime_now() == t0);
    REQUIRE(client.advance_to(t0 + 100'000, 5.0));
    CHECK(prepreg::process_steady_us() == t0 + 100'000);
    CHECK(client.reading().real_time_factor == 0.5);
    CHECK(client.reading().messages >= 2);
    REQUIRE(holds.size() >= 2);
    CHECK(holds.back().client == "cell_controller");
    CHECK(holds.back().until_utime == t0 + 100'000);
    CHECK_FALSE(holds.back().leaving);
  }
  bus.handle_for(std::chrono::milliseconds(0));
  REQUIRE_FALSE(holds.empty());
  CHECK(holds.back().leaving);  // the destructor lets the world go
  CHECK_FALSE(prepreg::simulated_time_active());
}

TEST_CASE("a client whose clock falls silent stops waiting and says so", "[sim_clock]") {
  drivers::LcmBus bus("memq://");
  drivers::SimClockClient client(bus, "cell_controller");
  // No world on this bus: with no silence allowed, the wait ends at once instead of for ever.
  CHECK_FALSE(client.advance_to(1'000'000'000, 0.0));
  CHECK(client.reading().messages == 0);
  std::atomic<bool> stop{true};
  CHECK_FALSE(client.advance_to(1'000'000'000, 60.0, &stop));  // a stop request ends it too
}

TEST_CASE("simulation clock message checks", "[lcm_checks]") {
  prepreg_lcm::sim_clock_t c = clock_at(1'000'000'000);
  CHECK(drivers::message_problem(c).empty());
  c.real_time_factor = -1;
  CHECK_THAT(drivers::message_problem(c), Catch::Contains("real_time_factor"));
  c = clock_at(1'000'000'000);
  c.state = 7;
  CHECK_THAT(drivers::message_problem(c), Catch::Contains("state"));
  c = clock_at(1'000'000'000);
  c.sim_us = -5;
  CHECK_THAT(drivers::message_problem(c), Catch::Contains("sim_us"));
  prepreg_lcm::sim_clock_hold_t h{};
  h.utime = 1;
  h.until_utime = 2;
  CHECK_THAT(drivers::message_problem(h), Catch::Contains("client"));
  h.client = "cell_controller";
  CHECK(drivers::message_problem(h).empty());
  h.until_utime = -1;
  CHECK_THAT(drivers::message_problem(h), Catch::Contains("until_utime"));
}
