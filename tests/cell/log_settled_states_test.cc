// A cell run's settled states read back from an lcm-logger log (cell/log_settled_states.h): the
// jaws from the logged arm joints by forward kinematics, releases from the gripper statuses,
// the tracked surface from SHEET_OBSERVED, through the live cell's settled-state detector.
#include <catch2/catch.hpp>
#include <lcm/lcm-cpp.hpp>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <map>
#include <random>

#include "cell/log_settled_states.h"
#include "drivers/iiwa_inverse_kinematics.h"
#include "drivers/lcm_channels.h"
#include "tests/cell/cell_rig.h"
#include "tests/support/lcm_log_writer.h"

namespace {

lcmt_iiwa_status arm_status(std::int64_t utime, const drivers::JointVector& q) {
  lcmt_iiwa_status m{};
  m.utime = utime;
  m.num_joints = 7;
  for (auto* v : {&m.joint_position_measured, &m.joint_velocity_estimated, &m.joint_position_commanded,
                  &m.joint_position_ipo, &m.joint_torque_measured, &m.joint_torque_commanded,
                  &m.joint_torque_external}) {
    v->assign(7, 0.0);
  }
  for (int j = 0; j < 7; ++j) m.joint_position_measured[j] = q(j);
  return m;
}

}  // namespace

TEST_CASE("settled states are read back from a cell run's log: jaws by forward kinematics, releases from the grippers",
          "[cell]") {
  testing_support::TempDir dir("log_states");
  const cell::CellConfig config = cell::read_cell_config(cell_test::write_files(dir, cell_test::default_files()));
  const twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
  const twin::SheetMesh& mesh = config.sheet.mesh;
  // Joints that put each arm's jaw at a position (the cell's own IK).
  std::map<std::pair<std::string, int>, drivers::JointVector> solved;  // (arm, raised) -> joints
  const auto joints_for = [&](const drivers::ArmConfig& arm, const twin::Vec3& jaw, int raised) {
    const auto key = std::make_pair(arm.name, raised);
    if (!solved.count(key)) {
      drivers::IkOptions options;
      options.restarts = 50;  // as the fake world's start-up: the answer is repeatable
      const drivers::IkResult ik =
          drivers::solve_inverse_kinematics(arm.arm(), drivers::flange_pose_for_jaw(arm, jaw), arm.home_rad, options);
      REQUIRE(ik.status == drivers::IkStatus::kConverged);
      solved[key] = ik.q;
    }
    return solved[key];
  };
  const int centre = plan.index_of("CENTER"), manual = plan.index_of("MANUAL");
  const std::string path = (dir / "run.lcmlog").string();
  {
    testing_support::LcmLogWriter log(path);
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.0005);
    const std::int64_t start_us = 1'800'000'000'000'000;
    const int cycles_per_phase = static_cast<int>(6.0 * config.cell.cycle_hz);
    for (int k = 0; k < 3 * cycles_per_phase; ++k) {
      const int phase = k / cycles_per_phase;  // 0 loaded, 1 CENTER raised 2 cm, 2 MANUAL let go
      const std::int64_t utime = start_us + static_cast<std::int64_t>(1e6 * k / config.cell.cycle_hz);
      for (const twin::Grasp& g : plan.grasps) {
        const drivers::GripperConfig* gripper = config.hardware.find_gripper(g.gripper);
        REQUIRE(gripper);
        if (!gripper->arm.empty()) {
          const drivers::ArmConfig* arm = config.hardware.find_arm(gripper->arm);
          const int raised = g.gripper == "CENTER" && phase >= 1 ? 1 : 0;
          const twin::Vec3 jaw = g.hold_position_m + twin::Vec3(0, 0, 0.02 * raised);
          log.write(std::string(drivers::channels::kIiwaStatusPrefix) + arm->name, utime,
                    arm_status(utime, joints_for(*arm, jaw, raised)));
        }
        prepreg_lcm::gripper_status_t gs{};
        gs.utime = utime;
        gs.state = prepreg_lcm::gripper_status_t::STATE_CLOSED;
        gs.width_m = 0.0f;
        gs.holding = !(g.gripper == "MANUAL" && phase >= 2);
        log.write(std::string(drivers::channels::kGripperStatusPrefix) + g.gripper, utime, gs);
      }
      prepreg_lcm::sheet_state_t sheet{};
      sheet.utime = utime;
      sheet.cycle_id = k;
      sheet.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
      sheet.num_vertices = mesh.vertex_count();
      for (const twin::Vec2& uv : mesh.rest_uv) {
        sheet.x_m.push_back(static_cast<float>(uv.x() - 0.5 + noise(rng)));
        sheet.y_m.push_back(static_cast<float>(0.02 * phase + noise(rng)));
        sheet.z_m.push_back(static_cast<float>(1.0 - uv.y() + noise(rng)));
      }
      sheet.num_observed_flags = mesh.vertex_count();
      sheet.vertex_observed.assign(static_cast<std::size_t>(mesh.vertex_count()), true);
      sheet.coverage = 1.0f;
      log.write(std::string(drivers::channels::kSheetObserved), utime, sheet);
    }
  }
  const cell::LoggedStates logged = cell::settled_states_from_log(path, config, plan);
  CHECK(logged.undecodable == 0);
  CHECK(logged.other_mesh == 0);
  REQUIRE(logged.states.size() == 3);
  const twin::Vec3 hold = plan.grasps[centre].hold_position_m;
  CHECK((logged.states[0].grasp_positions_m[centre] - hold).norm() < 0.001);
  CHECK((logged.states[1].grasp_positions_m[centre] - (hold + twin::Vec3(0, 0, 0.02))).norm() < 0.001);
  CHECK(logged.states[1].engaged[manual] == 1);
  CHECK(logged.states[2].engaged[manual] == 0);
  // The operator's gripper is where the plan holds it.
  CHECK((logged.states[0].grasp_positions_m[manual] - plan.grasps[manual].hold_position_m).norm() < 1e-12);
  CHECK(logged.states[2].vertices_m[0].y() == Approx(0.04).margin(0.001));
  CHECK(logged.states[2].cycle_noise_m == Approx(0.0005).epsilon(0.2));
  CHECK_THROWS_WITH(cell::settled_states_from_log((dir / "missing.lcmlog").string(), config, plan),
                    Catch::Contains("missing.lcmlog"));
}
