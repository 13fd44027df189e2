// The running cell: cycles publish the four channels and command the arms; the watchdog moves
// to DEGRADED / SAFE_HOLD (no robot commands) and back; malformed messages are dropped and counted.
#include <catch2/catch.hpp>

#include <cmath>

#include "drivers/iiwa_lcm.h"
#include "tests/cell/cell_fixture.h"

using Catch::Matchers::Contains;
using cell::CellState;

namespace {
// The watchdog tests need cycles, not accuracy: a sparser pixel stride keeps them fast.
cell_test::RigFiles fast_files() {
  cell_test::RigFiles f = cell_test::default_files();
  f.config["tracker"]["fusion"] = {{"pixel_stride", 4}};
  return f;
}
bool is(const cell::CycleReport& r, CellState s) { return r.state == s; }
}  // namespace

TEST_CASE("cycles publish observed, predicted, error, camera status and commands", "[cell][real_time]") {
  cell_test::CellUnderTest t(cell_test::default_files());
  REQUIRE(t.controller->startup() == CellState::kReady);
  std::vector<double> twin_ms, tracker_ms, cycle_ms;
  const int cycles = 8;
  for (int i = 0; i < cycles; ++i) {
    const cell::CycleReport r = t.run(1);
    CHECK(r.state == CellState::kRunning);
    CHECK(r.frames == 3);
    CHECK(r.tracked);
    CHECK(r.twin_ok);
    // On the simulation clock the twin steps in lockstep: its step runs beside the tracker and
    // the cycle takes it up before it judges, every cycle a period on.
    CHECK(r.twin_stepped);
    CHECK(r.twin_step_dt_s == Approx(t.controller->period_s()));
    twin_ms.push_back(r.twin_step_ms);
    tracker_ms.push_back(r.tracker_ms);
    cycle_ms.push_back(r.cycle_ms);
  }
  auto& n = t.listener.count;
  CHECK(n["SHEET_OBSERVED"] == cycles);
  CHECK(n["SHEET_PREDICTED"] == cycles);
  CHECK(n["PREDICTION_ERROR"] == cycles);
  CHECK(n["CAMERA_STATUS_CAM_FRONT"] == cycles);
  CHECK(n["CAMERA_STATUS_CAM_LEFT"] == cycles);
  CHECK(n["CAMERA_STATUS_CAM_RIGHT"] == cycles);
  const int vertices = t.controller->twin()->mesh().vertex_count();
  CHECK(t.listener.last_predicted.num_vertices == vertices);
  CHECK(t.listener.last_observed.num_observed_flags == vertices);
  CHECK(t.listener.last_observed.coverage > 0.8);
  const auto& e = t.listener.last_error;
  CHECK(e.num_vertex_errors == vertices);
  CHECK(e.num_compared > vertices / 2);
  // The twin predicts the sheet the cameras render (same model, same start): what is left is
  // the tracker's error against depth noise (mm).
  CHECK(e.mean_m < 0.01);
  CHECK(e.frames_utime <= e.utime);
  CHECK(t.listener.last_state.state == prepreg_lcm::cell_state_t::STATE_RUNNING);
  CHECK(t.listener.last_state.num_cameras_ok == 3);
  CHECK(t.responder->commands("LEFT") >= cycles - 1);
  CHECK(t.responder->commands("CENTER") >= cycles - 1);
  std::sort(twin_ms.begin(), twin_ms.end());
  std::sort(tracker_ms.begin(), tracker_ms.end());
  std::sort(cycle_ms.begin(), cycle_ms.end());
  WARN("median per cycle: twin step " << twin_ms[cycles / 2] << " ms, tracker " << tracker_ms[cycles / 2] << " ms, whole cycle "
                                      << cycle_ms[cycles / 2] << " ms (" << vertices << " twin vertices)");
}

TEST_CASE("watchdog: one camera dead -> DEGRADED, two -> SAFE_HOLD without commands, back -> RUNNING",
          "[cell][real_time]") {
  cell_test::CellUnderTest t(fast_files());
  REQUIRE(t.controller->startup() == CellState::kReady);
  REQUIRE(is(t.run(2), CellState::kRunning));

  t.cameras->kill(1);
  cell::CycleReport r = t.run(30, [](const auto& r) { return is(r, CellState::kDegraded); });
  REQUIRE(r.state == CellState::kDegraded);
  CHECK_THAT(t.controller->reason(), Contains("cam_left"));
  CHECK(r.commanded);  // two cameras are enough to go on

  t.cameras->kill(2);
  r = t.run(30, [](const auto& r) { return is(r, CellState::kSafeHold); });
  REQUIRE(r.state == CellState::kSafeHold);
  CHECK_THAT(t.controller->reason(), Contains("cam_left") && Contains("cam_right"));
  const auto commands = t.responder->all_commands();
  r = t.run(5);
  CHECK(r.state == CellState::kSafeHold);
  CHECK_FALSE(r.commanded);
  CHECK(t.responder->all_commands() == commands);
  CHECK(t.listener.last_state.state == prepreg_lcm::cell_state_t::STATE_SAFE_HOLD);

  t.cameras->revive(1);
  t.cameras->revive(2);
  r = t.run(40, [](const auto& r) { return is(r, CellState::kRunning); });
  REQUIRE(r.state == CellState::kRunning);
  t.run(1);
  CHECK(t.responder->all_commands() > commands);
}

TEST_CASE("watchdog: a camera knocked out of calibration while running -> DEGRADED naming the pair, then back",
          "[cell][real_time]") {
  cell_test::RigFiles files = fast_files();
  files.config["tracker"]["calibration"] = {{"every_n_cycles", 2}};
  cell_test::CellUnderTest t(files);
  REQUIRE(t.controller->startup() == CellState::kReady);
  REQUIRE(is(t.run(4), CellState::kRunning));
  t.cameras->bump(1, 0.02);  // cam_left, 2 cm sideways
  cell::CycleReport r = t.run(40, [](const auto& r) { return is(r, CellState::kDegraded); });
  REQUIRE(r.state == CellState::kDegraded);
  CHECK_THAT(t.controller->reason(), Contains("calibration check") && Contains("cam_left"));
  CHECK(r.commanded);  // tracking and commands go on; the engineer is told
  t.cameras->bump(1, 0.0);
  r = t.run(40, [](const auto& r) { return is(r, CellState::kRunning); });
  CHECK(r.state == CellState::kRunning);
}

TEST_CASE("watchdog: an arm whose status stops -> SAFE_HOLD naming it, then recovery", "[cell][real_time]") {
  cell_test::CellUnderTest t(fast_files());
  REQUIRE(t.controller->startup() == CellState::kReady);
  REQUIRE(is(t.run(2), CellState::kRunning));
  t.responder->silence("RIGHT", true);
  cell::CycleReport r = t.run(20, [](const auto& r) { return is(r, CellState::kSafeHold); });
  REQUIRE(r.state == CellState::kSafeHold);
  CHECK_THAT(t.controller->reason(), Contains("no arm status within 250 ms from RIGHT"));
  const auto commands = t.responder->all_commands();
  CHECK_FALSE(t.run(3).commanded);
  CHECK(t.responder->all_commands() == commands);
  t.responder->silence("RIGHT", false);
  r = t.run(10, [](const auto& r) { return is(r, CellState::kRunning); });
  CHECK(r.state == CellState::kRunning);
}

TEST_CASE("watchdog: SIM_FAULT twin diverge -> SAFE_HOLD only with fault injection, then recovery", "[cell][real_time]") {
  auto fault = [](drivers::LcmBus& bus, bool active) {
    prepreg_lcm::sim_fault_t f{};
    f.utime = drivers::utime_now();
    f.target = "twin";
    f.fault = "diverge";
    f.active = active;
    REQUIRE(bus.publish(std::string(drivers::channels::kSimFault), f));
  };
  SECTION("without --fault-injection the cell ignores it") {
    cell_test::CellUnderTest t(fast_files(), false);
    REQUIRE(t.controller->startup() == CellState::kReady);
    fault(t.bus, true);
    const cell::CycleReport r = t.run(3);
    INFO("state " << cell::to_string(r.state) << ": " << t.controller->reason());
    CHECK(r.state == CellState::kRunning);
    CHECK(r.twin_stepped);
  }
  SECTION("with --fault-injection the twin step fails and nothing of it is published") {
    cell_test::CellUnderTest t(fast_files(), true);
    REQUIRE(t.controller->startup() == CellState::kReady);
    REQUIRE(is(t.run(2), CellState::kRunning));
    fault(t.bus, true);
    cell::CycleReport r = t.run(3, [](const auto& r) { return is(r, CellState::kSafeHold); });
    REQUIRE(r.state == CellState::kSafeHold);
    CHECK_FALSE(r.twin_stepped);
    CHECK_THAT(t.controller->reason(), Contains("twin failure"));
    const int predicted = t.listener.count["SHEET_PREDICTED"];
    const auto commands = t.responder->all_commands();
    r = t.run(3);
    CHECK(r.state == CellState::kSafeHold);
    CHECK(t.listener.count["SHEET_PREDICTED"] == predicted);
    CHECK(t.responder->all_commands() == commands);
    fault(t.bus, false);
    r = t.run(5, [](const auto& r) { return is(r, CellState::kRunning); });
    CHECK(r.state == CellState::kRunning);
    t.run(1);
    CHECK(t.listener.count["SHEET_PREDICTED"] > predicted);
    for (float z : t.listener.last_predicted.z_m) REQUIRE(std::isfinite(z));
  }
}

TEST_CASE("a twin slower than the cycle: cycles do not wait for it, its steps span the cycles, in lockstep they wait",
          "[cell][real_time]") {
  auto slow = [](drivers::LcmBus& bus, bool active) {
    prepreg_lcm::sim_fault_t f{};
    f.utime = drivers::utime_now();
    f.target = "twin";
    f.fault = "slow";  // each step takes three periods longer
    f.active = active;
    REQUIRE(bus.publish(std::string(drivers::channels::kSimFault), f));
  };
  for (const bool lockstep : {false, true}) {
    DYNAMIC_SECTION((lockstep ? "lockstep" : "own pace")) {
      cell_test::RigFiles files = fast_files();
      // What a cycle waits for on the wall: the twin's own pace is for real hardware's clock.
      files.config["cell"]["clock"] = "wall";
      files.config["cell"]["twin_lockstep"] = lockstep;
      // The test tells a cycle that waited for the stalled step from one that did not by their
      // times, so the stall (three periods) must be far longer than a cycle's own work (about
      // 50 ms here, more on a busy machine): at 3 Hz it is 1 s, and a cycle that does not wait
      // has half of it, 10x its nominal time. (Still a wall-clock test: [real_time].)
      files.config["cell"]["cycle_hz"] = 3;
      cell_test::CellUnderTest t(files, true);
      REQUIRE(t.controller->startup() == CellState::kReady);
      REQUIRE(is(t.run(2), CellState::kRunning));
      slow(t.bus, true);
      t.controller->handle_bus(0);
      const double period_s = t.controller->period_s();
      const double stall_ms = 3e3 * period_s;
      const int predicted_before = t.listener.count["SHEET_PREDICTED"];
      int cycles = 0, steps = 0, quick = 0;
      double covered_s = 0.0;
      // Until four steps were taken up (the first may predate the fault). The cameras pace the
      // cycles at 30 per second at most, so four 1 s steps take at most about 130 of them; 300
      // only bounds the loop.
      for (; cycles < (lockstep ? 6 : 300) && !(steps >= 4 && !lockstep); ++cycles) {
        const cell::CycleReport r = t.run(1);
        CHECK(r.state == CellState::kRunning);  // a slow twin is no failure
        CHECK(r.twin_ok);
        if (r.twin_stepped) {
          ++steps;
          covered_s += r.twin_step_dt_s;
          // (Without lockstep the first step taken up here may have started before the fault.)
          if (lockstep || steps > 1) CHECK(r.twin_step_ms >= stall_ms);
          // The step after a stalled one spans the cycles that ran meanwhile: its dt covers them.
          if (!lockstep && steps > 2) CHECK(r.twin_step_dt_s >= 2 * period_s - 1e-9);
        }
        quick += r.cycle_ms < 0.5 * stall_ms;
      }
      INFO("steps " << steps << " in " << cycles << " cycles, " << quick << " cycles under half the stall, dt covered "
                    << covered_s << " s");
      CHECK(t.listener.count["SHEET_PREDICTED"] == predicted_before + cycles);  // every cycle compares
      if (lockstep) {
        CHECK(steps == cycles);  // every cycle waited for its step
        CHECK(quick == 0);
        CHECK(covered_s == Approx(cycles * period_s));
      } else {
        CHECK(steps >= 4);
        CHECK(steps < cycles);
        CHECK(quick >= cycles / 2);
        // The steps' dt add up to no more than the cycles they can have spanned.
        CHECK(covered_s <= (cycles + 1) * period_s + 1e-9);
      }
      slow(t.bus, false);
      const cell::CycleReport after = t.run(30, [](const auto& r) { return r.twin_stepped && r.twin_step_ms < 100.0; });
      CHECK(after.twin_stepped);
    }
  }
}

TEST_CASE("malformed arm status and fault messages are dropped and counted, never acted on", "[cell][real_time]") {
  cell_test::CellUnderTest t(fast_files(), true);
  REQUIRE(t.controller->startup() == CellState::kReady);
  REQUIRE(is(t.run(1), CellState::kRunning));
  const auto dropped = t.controller->dropped_messages();
  // LEFT's driver goes quiet so that only the bad statuses arrive on its channel.
  t.responder->silence("LEFT", true);
  t.controller->handle_bus(20);
  const drivers::JointVector measured = *t.controller->robots()->arm(0).measured_rad;
  const auto statuses = t.controller->robots()->arm(0).statuses;
  // Six joints, a NaN joint, bytes that are no status at all, a fault with a count lie.
  drivers::JointVector q = drivers::JointVector::Zero();
  lcmt_iiwa_status six = drivers::make_iiwa_status(drivers::utime_now(), q, q, q);
  for (auto* v : {&six.joint_position_measured, &six.joint_velocity_estimated, &six.joint_position_commanded,
                  &six.joint_position_ipo, &six.joint_torque_measured, &six.joint_torque_commanded,
                  &six.joint_torque_external}) {
    v->resize(6);
  }
  six.num_joints = 6;
  REQUIRE(t.bus.publish("IIWA_STATUS_LEFT", six));
  lcmt_iiwa_status bad = drivers::make_iiwa_status(drivers::utime_now(), q, q, q);
  bad.joint_position_measured[2] = std::nan("");
  t.bus.publish("IIWA_STATUS_LEFT", bad);  // may be refused already on publishing; then raw below
  const std::uint8_t junk[7] = {1, 2, 3, 4, 5, 6, 7};
  REQUIRE(t.bus.publish_raw("IIWA_STATUS_LEFT", junk, sizeof junk));
  REQUIRE(t.bus.publish_raw("SIM_FAULT", junk, sizeof junk));
  prepreg_lcm::sim_fault_t unknown{};
  unknown.target = "twin";
  unknown.fault = "melt";
  unknown.active = true;
  // The bus refuses to publish it, so it goes out raw: the cell's side must drop it too.
  CHECK_FALSE(t.bus.publish("SIM_FAULT", unknown));
  std::vector<std::uint8_t> bytes(unknown.getEncodedSize());
  REQUIRE(unknown.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == static_cast<int>(bytes.size()));
  REQUIRE(t.bus.publish_raw("SIM_FAULT", bytes.data(), bytes.size()));
  t.controller->handle_bus(0);
  CHECK(t.controller->dropped_messages() >= dropped + 4);
  CHECK(t.controller->robots()->arm(0).malformed >= 1);
  CHECK(t.controller->robots()->arm(0).statuses == statuses);  // none of them counted as a status
  CHECK(*t.controller->robots()->arm(0).measured_rad == measured);
  t.responder->silence("LEFT", false);
  CHECK(is(t.run(2), CellState::kRunning));
}
