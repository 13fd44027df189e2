// The whole fake world: the initial load (arms at the IK solutions, the sheet hanging at rest with
// the grasped points at the hold positions) and a short run on memq:// with the cameras served
// as emulated V4L2 devices and read back through the real V4L2 back-end.

#include <unistd.h>

#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include <catch2/catch.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_fault_t.hpp>

#include "drivers/iiwa_lcm.h"
#include "drivers/lcm_channels.h"
#include "drivers/monitored_depth_camera.h"
#include "drivers/v4l2_d415_camera.h"
#include "sim_hw/cell_world.h"
#include "sim_hw/emulated_v4l2_io.h"
#include "sim_hw/world_start.h"
#include "tests/sim_hw/world_test_files.h"

namespace {

using namespace std::chrono_literals;

}  // namespace

TEST_CASE("initial load: the arms hold the jaws and the sheet hangs at rest from the hold positions", "[world]") {
  const std::string src = PREPREG_SOURCE_DIR;
  const sim_hw::WorldConfig config =
      sim_hw::read_world_config(src + "/cell/examples/fake_cell.json", src + "/sim_hw/examples/fake_world.json");
  CHECK(config.sheet.mesh.triangles.size() > 1800);  // its own mesh, not the twin's 1500
  const sim_hw::WorldStart start = sim_hw::plan_world_start(config);
  REQUIRE(start.grasps.size() == 4);
  sim_hw::TrueSheet sheet(config.sheet, config.material);
  REQUIRE(sheet.load(start.grasps).usable());
  const twin::VecX x = sheet.positions();
  for (const sim_hw::HeldGrasp& g : start.grasps) {
    const twin::Clamp clamp(sheet.mesh(), g.clamp);
    const twin::Vec3 hold = config.plan.grasps[config.plan.index_of(g.clamp.id)].hold_position_m;
    INFO(g.clamp.id);
    CHECK((clamp.material_point_position(x) - hold).norm() < 1e-3);
    CHECK((g.jaw_pose.translation() - hold).norm() < 1e-3);  // the arm's jaw (FK) or the operator's
    if (const auto* gr = config.hardware.find_gripper(g.clamp.id); gr && !gr->arm.empty()) {
      const drivers::ArmConfig& arm = *config.hardware.find_arm(gr->arm);
      const auto flange = arm.arm().flange_in_cell(start.arm_q.at(arm.name));
      CHECK((drivers::jaw_position(arm, flange) - hold).norm() < 1e-3);
      CHECK(arm.arm().within_limits(start.arm_q.at(arm.name)));
    }
  }
  CHECK(sheet.sag_m() > 0.05);
  CHECK(sheet.sag_m() < 0.8);
  // At rest: a second of real-time physics barely moves it.
  for (int i = 0; i < 30; ++i) sheet.step(1.0 / 30);
  CHECK(sheet.stats().failures == 0);
  CHECK((sheet.positions() - x).cwiseAbs().maxCoeff() < 5e-3);
}

TEST_CASE("cell world: a short run on memq serves arms, grippers, truth, faults and camera frames", "[world]") {
  testing_support::TempDir dir("cell_world");
  const world_test::WorldFiles files = world_test::make_world_files(dir);
  drivers::LcmBus bus("memq://");
  sim_hw::CellWorld world(sim_hw::read_world_config(files.cell, files.world), bus);

  std::vector<lcmt_iiwa_status> left;
  int right_statuses = 0, truths = 0, truth_vertices = 0;
  bool left_holding = false, manual_holding = false;
  bus.subscribe<lcmt_iiwa_status>("IIWA_STATUS_LEFT", [&](const lcmt_iiwa_status& s) { left.push_back(s); });
  bus.subscribe<lcmt_iiwa_status>("IIWA_STATUS_RIGHT", [&](const lcmt_iiwa_status&) { ++right_statuses; });
  bus.subscribe<prepreg_lcm::gripper_status_t>("GRIPPER_STATUS_LEFT", [&](const auto& s) { left_holding = s.holding; });
  bus.subscribe<prepreg_lcm::gripper_status_t>("GRIPPER_STATUS_MANUAL", [&](const auto& s) { manual_holding = s.holding; });
  bus.subscribe<prepreg_lcm::sheet_state_t>("SIM_SHEET_TRUTH", [&](const prepreg_lcm::sheet_state_t& s) {
    ++truths;
    truth_vertices = s.num_vertices;
  });

  // The front camera read through the V4L2 back-end over the emulation, on its own thread.
  const sim_hw::WorldConfig config = sim_hw::read_world_config(files.cell, files.world);
  const sim_hw::WorldCamera& front = config.cameras[0];
  auto io = std::make_shared<sim_hw::EmulatedV4l2Io>(std::map<std::string, std::string>{
      {front.depth_device, front.node_prefix + "_depth"}, {front.color_device, front.node_prefix + "_color"}});
  drivers::MonitoredDepthCamera reader(std::make_unique<drivers::V4l2D415Camera>(io));
  drivers::CameraConfig v4l2 = front.config;
  v4l2.backend = "v4l2";
  v4l2.uri = "depth=" + front.depth_device + ",color=" + front.color_device;
  REQUIRE(reader.configure(v4l2).ok);
  REQUIRE(reader.activate().ok);
  // The world runs on its simulation clock, at most at real time (the reader thread reads on the
  // wall), for the given simulated seconds.
  const auto run = [&](double seconds) { REQUIRE(world.run_until(world.sim_time_s() + seconds)); };
  // frames counts every frame handed out: a stale one (rendered late on a loaded machine) is
  // still a frame the device delivered.
  std::atomic<int> frames{0}, valid_pixels{0}, lost{0};
  std::array<std::atomic<int>, static_cast<std::size_t>(drivers::ReadStatus::kCorrupt) + 1> by_status{};
  std::atomic<bool> reading{true};
  std::thread read_thread([&] {
    drivers::DepthFrame f;
    while (reading) {
      const drivers::ReadStatus status = reader.read(f);
      ++by_status.at(static_cast<std::size_t>(status));
      if (status == drivers::ReadStatus::kLost) ++lost;
      if (status != drivers::ReadStatus::kFrame && status != drivers::ReadStatus::kStale &&
          status != drivers::ReadStatus::kFrozen)
        continue;
      ++frames;
      int n = 0;
      for (auto d : f.depth_mm) n += d > 0;
      valid_pixels = n;
    }
  });
  const auto reads = [&] {
    std::string text;
    for (std::size_t i = 0; i < by_status.size(); ++i)
      text += std::string(drivers::to_string(static_cast<drivers::ReadStatus>(i))) + " " +
              std::to_string(by_status[i]) + "; ";
    return text + "rig rendered " + std::to_string(world.snapshot().camera_frames.front().second);
  };
  // A failed REQUIRE unwinds through here: stop and join the reader rather than terminate.
  struct StopReader {
    std::atomic<bool>& reading;
    std::thread& thread;
    ~StopReader() {
      reading = false;
      if (thread.joinable()) thread.join();
    }
  } stop_reader{reading, read_thread};

  const double running_since_s = world.sim_time_s();
  run(0.5);
  REQUIRE_FALSE(left.empty());
  const drivers::JointVector q0 = *drivers::measured_positions(left.back());
  CHECK(left.back().num_joints == 7);
  CHECK(left_holding);
  CHECK(manual_holding);
  // Command LEFT's A1 by +0.1 rad, plus one malformed command.
  drivers::JointVector target = q0;
  target[0] += 0.1;
  bus.publish("IIWA_COMMAND_LEFT", drivers::make_iiwa_command(drivers::utime_now(), target));
  lcmt_iiwa_command bad = drivers::make_iiwa_command(drivers::utime_now(), target);
  bad.joint_position[1] = std::nan("");
  // Sent as raw bytes: the bus refuses to publish a message failing its checks.
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(bad.getEncodedSize()));
  REQUIRE(bad.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == static_cast<int>(bytes.size()));
  bus.publish_raw("IIWA_COMMAND_LEFT", bytes.data(), bytes.size());
  lcmt_iiwa_command torque = drivers::make_iiwa_command(drivers::utime_now(), target);
  torque.num_torques = 7;
  torque.joint_torque.assign(7, 1.0);
  bus.publish("IIWA_COMMAND_LEFT", torque);
  prepreg_lcm::sim_fault_t twin_fault{};
  twin_fault.target = "twin";
  twin_fault.fault = "diverge";
  twin_fault.active = true;
  bus.publish("SIM_FAULT", twin_fault);
  run(0.8);
  // The arm moves a fixed step per status tick (of simulated time): 0.8 s is about 8x what it needs.
  const auto reached = [&] {
    return (*drivers::measured_positions(left.back()))[0] == Approx(q0[0] + 0.1).margin(1e-6);
  };
  for (int i = 0; i < 200 && !reached(); ++i) run(0.05);
  const drivers::JointVector q1 = *drivers::measured_positions(left.back());
  CHECK(q1[0] == Approx(q0[0] + 0.1).margin(1e-6));
  CHECK(left.back().joint_position_commanded[0] == Approx(target[0]));
  // LEFT's gripper carried its patch of the true sheet along with the jaw.
  const sim_hw::SimulatedArm& left_arm = *world.arms()[0];
  REQUIRE(left_arm.name() == "LEFT");
  const twin::Clamp left_clamp(world.sheet().mesh(), config.plan.grasps[config.plan.index_of("LEFT")].clamp);
  const twin::Vec3 hold = config.plan.grasps[config.plan.index_of("LEFT")].hold_position_m;
  CHECK((left_arm.jaw_pose().translation() - hold).norm() > 0.03);  // A1 +0.1 rad: ~4.5 cm
  // The sheet follows at its physics steps: two more, the second begun with the arm at rest.
  const std::uint64_t version_at_rest = world.sheet().version();
  for (int i = 0; i < 200 && world.sheet().version() < version_at_rest + 2; ++i) run(0.05);
  INFO("sheet steps " << world.sheet().stats().steps << ", failures " << world.sheet().stats().failures
                      << ", last step " << world.sheet().stats().last_step_ms << " ms");
  REQUIRE(world.sheet().version() >= version_at_rest + 2);
  CHECK((left_clamp.material_point_position(world.sheet().positions()) - left_arm.jaw_pose().translation()).norm() < 2e-3);

  // The operator lets go of the MANUAL grasp on GRIPPER_COMMAND_MANUAL.
  prepreg_lcm::gripper_command_t open{};
  open.utime = drivers::utime_now();
  open.action = prepreg_lcm::gripper_command_t::ACTION_OPEN;
  open.width_m = 0.05f;
  bus.publish("GRIPPER_COMMAND_MANUAL", open);
  run(0.1);
  CHECK_FALSE(manual_holding);
  CHECK(left_holding);

  // Status silence on RIGHT, then the run's counters.
  prepreg_lcm::sim_fault_t silent{};
  silent.target = "RIGHT";
  silent.fault = "status_silent";
  silent.active = true;
  bus.publish("SIM_FAULT", silent);
  run(0.05);
  const int right_before = right_statuses;
  run(0.3);
  CHECK(right_statuses == right_before);
  const std::size_t left_count = left.size();
  // Statuses at 100 Hz of simulated time, every one of them, however busy the machine.
  const double ran_s = world.sim_time_s() - running_since_s;
  INFO("LEFT statuses " << left_count << " in " << ran_s << " s");
  CHECK(static_cast<double>(left_count) >= 100.0 * ran_s - 1);
  CHECK(static_cast<double>(left_count) <= 100.0 * ran_s + 2);

  // A dead camera: its nodes are unplugged and the reader sees the device lost; cleared, it
  // comes back and frames arrive again. First the reader must be getting frames (a sanitizer on
  // a loaded machine renders slowly). Frames already in the reader's buffers, or rendered before
  // the fault landed, may still arrive after it is sent (a loaded CI machine saw two); none may
  // once the reader has seen the device lost.
  for (int i = 0; i < 40 && frames < 2; ++i) run(0.2);
  INFO("reads before the fault: " << reads());
  REQUIRE(frames >= 2);
  prepreg_lcm::sim_fault_t dead{};
  dead.target = "cam_front";
  dead.fault = "dead";
  dead.active = true;
  bus.publish("SIM_FAULT", dead);
  for (int i = 0; i < 160 && lost == 0; ++i) run(0.05);
  INFO("reads after the fault: " << reads());
  REQUIRE(lost > 0);
  const int frames_after_lost = frames;
  run(0.6);
  CHECK(frames == frames_after_lost);
  dead.active = false;
  bus.publish("SIM_FAULT", dead);
  const int frames_at_clear = frames;
  // The reader reopens the device with backoff; under a sanitizer or a loaded machine that and
  // the first renders take a few seconds.
  for (int i = 0; i < 40 && frames - frames_at_clear < 2; ++i) run(0.2);
  CHECK(frames - frames_at_clear >= 2);
  // Truth goes out at truth_hz of simulated time.
  for (int i = 0; i < 100 && truths < 2; ++i) run(0.1);

  reading = false;
  read_thread.join();
  run(0.2);
  const sim_hw::WorldSnapshot s = world.snapshot();
  CHECK(s.counters.arm_commands == 1);
  // The NaN command is dropped by the bus's check; the torque command (valid LCM, not position
  // control) by the arm, unless the bus's check refused it already.
  CHECK(s.counters.arm_commands_rejected + bus.counters().rejected + bus.counters().publish_failures == 2);
  CHECK(s.counters.faults_not_ours == 1);
  CHECK(s.counters.faults_applied == 3);
  // One truth at each 1/truth_hz of simulated time from t = 0, each one received.
  CHECK(truths >= 2);
  const auto expected_truths = static_cast<std::uint64_t>(std::floor(s.sim_time_s * config.truth_hz + 1e-9)) + 1;
  CHECK(s.counters.truth_published + 1 >= expected_truths);
  CHECK(s.counters.truth_published <= expected_truths + 1);
  // All but the one at time 0, which the constructor sent before the test subscribed.
  CHECK(static_cast<std::uint64_t>(truths) + 1 == s.counters.truth_published);
  CHECK(truth_vertices == world.sheet().mesh().vertex_count());
  CHECK(s.physics.failures == 0);
  CHECK(s.holding.size() == 3);  // all but MANUAL
  CHECK(s.counters.gripper_commands == 1);
  CHECK(frames >= 4);  // two before the fault, two after it cleared
  CHECK(valid_pixels > 848 * 480 / 4);  // it sees the sheet, table and floor
  CHECK(s.camera_frames.size() == 3);
  for (const auto& [name, n] : s.camera_frames) CHECK(n >= 5);
}

TEST_CASE("cell_world: a bad config exits 1 naming the file and the field", "[world]") {
  testing_support::TempDir dir("cell_world_tool");
  world_test::WorldEdits e;
  e.world = [](nlohmann::json& w) { w["physics"]["truth_hz"] = "fast"; };
  const world_test::WorldFiles files = world_test::make_world_files(dir, e);
  const std::string command = std::string(CELL_WORLD_EXE) + " --config " + files.cell + " --world " + files.world +
                              " --lcm memq:// --max-seconds 1 --quiet 2>" + (dir / "err.txt").string();
  const int status = std::system(command.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 1);
  std::ifstream err(dir / "err.txt");
  const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  CHECK_THAT(text, Catch::Contains("world.json") && Catch::Contains("physics.truth_hz"));
}

TEST_CASE("cell world on its clock: a lockstep client holds it, and a run repeats exactly", "[world]") {
  testing_support::TempDir dir("cell_world_lockstep");
  const world_test::WorldFiles files = world_test::make_world_files(dir);
  const auto run = [&](std::vector<twin::VecX>& sheets) {
    drivers::LcmBus bus("memq://");
    sim_hw::WorldClockOptions lockstep;
    lockstep.max_real_time_factor = 0;  // as fast as it goes: only the hold limits it
    lockstep.lockstep = {"tester"};
    sim_hw::CellWorld world(sim_hw::read_world_config(files.cell, files.world), bus, lockstep);
    const auto hold = [&](double until_s) {
      prepreg_lcm::sim_clock_hold_t m{};
      m.utime = drivers::utime_now();
      m.client = "tester";
      m.until_utime = world.clock().epoch_us() + std::llround(until_s * 1e6);
      REQUIRE(bus.publish(std::string(drivers::channels::kSimClockHold), m));
    };
    lcmt_iiwa_status left{};
    bus.subscribe<lcmt_iiwa_status>("IIWA_STATUS_LEFT", [&](const lcmt_iiwa_status& s) { left = s; });
    // Not heard yet: the clock stays at 0 (the wait gives up after its patience).
    CHECK_FALSE(world.run_until(0.1, std::chrono::milliseconds(50)));
    CHECK(world.sim_time_s() == 0.0);
    hold(0.5);
    REQUIRE(world.run_until(0.5));
    CHECK_FALSE(world.run_until(0.6, std::chrono::milliseconds(50)));  // held at the client's 0.5 s
    CHECK(world.sim_time_s() == Approx(0.5));
    CHECK(world.snapshot().held_by == "tester");
    // A command sent before the hold acts at the time the clock was held at, whatever the wall.
    const auto measured = drivers::measured_positions(left);
    REQUIRE(measured);
    drivers::JointVector target = *measured;
    target[0] += 0.05;
    bus.publish("IIWA_COMMAND_LEFT", drivers::make_iiwa_command(drivers::utime_now(), target));
    for (double t = 0.6; t <= 2.0 + 1e-9; t += 0.1) {
      hold(t);
      REQUIRE(world.run_until(t));
      sheets.push_back(world.sheet().positions());
    }
  };
  std::vector<twin::VecX> first, second;
  run(first);
  run(second);
  REQUIRE(first.size() == second.size());
  double moved = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    CHECK((first[i] - second[i]).cwiseAbs().maxCoeff() == 0.0);
    moved = std::max(moved, (first[i] - first.front()).cwiseAbs().maxCoeff());
  }
  CHECK(moved > 0.005);  // the commanded arm carried the sheet: the runs compare a moving sheet
}
