// The fake world's simulation clock: without lockstep clients it may run on without limit; a
// lockstep client holds it at 0 until heard, then up to its last hold; a client that leaves is
// let go, one that falls silent while the clock waits on it is dropped with a notice; each
// advance is published on SIM_CLOCK, a held clock says so, and the process runs on it.
#include <catch2/catch.hpp>

#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>

#include "drivers/lcm_channels.h"
#include "sim_hw/world_clock.h"

namespace {

void hold(drivers::LcmBus& bus, const sim_hw::WorldClock& clock, const std::string& client, double until_s,
          bool leaving = false) {
  prepreg_lcm::sim_clock_hold_t m{};
  m.utime = clock.utime();
  m.client = client;
  m.until_utime = clock.epoch_us() + std::llround(until_s * 1e6);
  m.leaving = leaving;
  REQUIRE(bus.publish(std::string(drivers::channels::kSimClockHold), m));
  while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
  }
}

}  // namespace

TEST_CASE("world clock: free without lockstep clients, published, the process on it", "[world_clock]") {
  drivers::LcmBus bus("memq://");
  std::vector<prepreg_lcm::sim_clock_t> heard;
  bus.subscribe<prepreg_lcm::sim_clock_t>(std::string(drivers::channels::kSimClock),
                                          [&](const prepreg_lcm::sim_clock_t& m) { heard.push_back(m); });
  sim_hw::WorldClock clock({0.0, {}, 30.0}, bus);
  CHECK(clock.limit_us() == sim_hw::WorldClock::kUnlimited);
  CHECK(clock.sim_us() == 0);
  CHECK(drivers::utime_now() == clock.epoch_us());
  REQUIRE(clock.pace_to(250'000, nullptr));  // no rate limit: no wait
  clock.advance_to(250'000);
  clock.publish(false);
  clock.advance_to(100'000);  // never back
  CHECK(clock.sim_us() == 250'000);
  CHECK(drivers::utime_now() == clock.epoch_us() + 250'000);
  bus.handle_for(std::chrono::milliseconds(0));
  REQUIRE(heard.size() == 1);
  CHECK(heard[0].sim_us == 250'000);
  CHECK(heard[0].utime == clock.utime());
  CHECK(heard[0].state == prepreg_lcm::sim_clock_t::STATE_RUNNING);
}

TEST_CASE("world clock: a lockstep client holds it, from 0 until heard, then to its last hold", "[world_clock]") {
  drivers::LcmBus bus("memq://");
  std::vector<prepreg_lcm::sim_clock_t> heard;
  bus.subscribe<prepreg_lcm::sim_clock_t>(std::string(drivers::channels::kSimClock),
                                          [&](const prepreg_lcm::sim_clock_t& m) { heard.push_back(m); });
  sim_hw::WorldClock clock({0.0, {"cell_controller", "viewer"}, 30.0}, bus);
  CHECK(clock.limit_us() == 0);
  CHECK_THAT(clock.held_by(), Catch::Contains("not heard yet"));
  hold(bus, clock, "cell_controller", 0.1);
  CHECK(clock.limit_us() == 0);  // the viewer is not heard yet
  CHECK(clock.held_by() == "viewer (not heard yet)");
  hold(bus, clock, "viewer", 0.3);
  CHECK(clock.limit_us() == 100'000);
  CHECK(clock.held_by() == "cell_controller");
  hold(bus, clock, "someone_else", 0.0);  // not one we wait for: ignored
  CHECK(clock.limit_us() == 100'000);
  hold(bus, clock, "cell_controller", 0.05);  // a hold never takes back what was allowed
  CHECK(clock.limit_us() == 100'000);
  clock.advance_to(100'000);
  heard.clear();
  clock.wait_held(std::chrono::milliseconds(1));  // held: says so (the first time at once)
  bus.handle_for(std::chrono::milliseconds(0));
  REQUIRE_FALSE(heard.empty());
  CHECK(heard.back().state == prepreg_lcm::sim_clock_t::STATE_HELD);
  CHECK(heard.back().held_by == "cell_controller");
  hold(bus, clock, "cell_controller", 1.0, /*leaving=*/true);
  CHECK(clock.limit_us() == 300'000);  // the viewer's
  hold(bus, clock, "viewer", 0.3, /*leaving=*/true);
  CHECK(clock.limit_us() == sim_hw::WorldClock::kUnlimited);
}

TEST_CASE("world clock: a client silent while the clock waits on it is dropped with a notice", "[world_clock]") {
  drivers::LcmBus bus("memq://");
  // No silence allowed: a heard client the clock waits on is dropped at the next look.
  sim_hw::WorldClock clock({0.0, {"cell_controller"}, 0.0}, bus);
  CHECK(clock.limit_us() == 0);  // never heard: waited for, however long
  CHECK(clock.clients_dropped() == 0);
  hold(bus, clock, "cell_controller", 0.2);
  CHECK(clock.limit_us() == 200'000);  // not waited on yet: kept
  clock.advance_to(200'000);
  CHECK(clock.limit_us() == sim_hw::WorldClock::kUnlimited);
  CHECK(clock.clients_dropped() == 1);
  CHECK_THAT(clock.take_notice(), Catch::Contains("cell_controller silent"));
  CHECK(clock.take_notice().empty());
}
