// The fake world's devices on their own: the simulated iiwa (follows commands within the
// limits, fills its status, counts malformed commands), grippers gripping and releasing a small
// true sheet, and the world config's errors naming file and field.

#include <cmath>

#include <catch2/catch.hpp>

#include "drivers/iiwa_lcm.h"
#include "sim_hw/simulated_arm.h"
#include "sim_hw/simulated_gripper.h"
#include "sim_hw/world_config.h"
#include "sim_hw/world_start.h"
#include "tests/sim_hw/world_test_files.h"
#include "twin/mesh/sheet_mesh.h"

namespace {

using drivers::JointVector;

drivers::ArmConfig iiwa7() {
  drivers::ArmConfig a;
  a.name = "LEFT";
  a.model = drivers::IiwaModel::kIiwa7R800;
  return a;
}

}  // namespace

TEST_CASE("arm: follows a command at no more than the velocity limits, then holds it", "[world]") {
  const JointVector start = (JointVector() << 0, 0.5, 0, -1.2, 0, 0.8, 0).finished();
  sim_hw::SimulatedArm arm(iiwa7(), start);
  const JointVector target = start + (JointVector() << 0.6, -0.3, 0.4, 0.2, -0.5, 0.3, 1.0).finished();
  REQUIRE(arm.command(drivers::make_iiwa_command(1, target)));
  const JointVector vmax = drivers::iiwa_parameters(drivers::IiwaModel::kIiwa7R800).velocity_max_rad_s;
  const double dt = 0.01;
  JointVector previous = arm.q();
  int ticks = 0;
  while ((arm.q() - target).norm() > 1e-9 && ticks < 1000) {
    arm.tick(dt);
    ++ticks;
    for (int j = 0; j < 7; ++j) CHECK(std::abs(arm.q()[j] - previous[j]) <= vmax[j] * dt * (1 + 1e-9));
    previous = arm.q();
  }
  CHECK((arm.q() - target).norm() < 1e-9);
  // The slowest joint (A7: 1.0 rad at 180 deg/s ~ 0.32 s ... A2/A1 at 98 deg/s) sets the time.
  CHECK(ticks > 30);
  CHECK(ticks < 200);
  arm.tick(dt);
  CHECK(arm.velocity().norm() == 0.0);

  // Beyond the position limit: the arm stops at the limit.
  JointVector far = target;
  far[0] = 4.0;  // A1 limit is 170 deg = 2.967 rad
  REQUIRE(arm.command(drivers::make_iiwa_command(2, far)));
  for (int i = 0; i < 500; ++i) arm.tick(dt);
  CHECK(arm.q()[0] == Approx(170.0 * M_PI / 180.0).margin(1e-9));
}

TEST_CASE("arm: status fields and malformed commands", "[world]") {
  const JointVector start = (JointVector() << 0.1, 0.5, 0, -1.2, 0, 0.8, 0).finished();
  sim_hw::SimulatedArm arm(iiwa7(), start);
  JointVector target = start;
  target[3] += 0.1;
  REQUIRE(arm.command(drivers::make_iiwa_command(1, target)));
  arm.tick(0.01);
  const lcmt_iiwa_status s = arm.status(12345);
  CHECK(s.utime == 12345);
  REQUIRE(s.num_joints == 7);
  REQUIRE(s.joint_position_measured.size() == 7u);
  CHECK(s.joint_position_measured[3] == Approx(arm.q()[3]));
  CHECK(s.joint_position_commanded[3] == Approx(target[3]));
  CHECK(s.joint_velocity_estimated[3] == Approx((arm.q()[3] - start[3]) / 0.01));
  CHECK(s.joint_velocity_estimated[3] > 0);
  CHECK(s.joint_torque_measured.size() == 7u);
  CHECK(drivers::measured_positions(s).has_value());

  lcmt_iiwa_command six = drivers::make_iiwa_command(2, start);
  six.num_joints = 6;
  six.joint_position.resize(6);
  lcmt_iiwa_command nan = drivers::make_iiwa_command(3, start);
  nan.joint_position[2] = std::nan("");
  lcmt_iiwa_command torque = drivers::make_iiwa_command(4, start);
  torque.num_torques = 7;
  torque.joint_torque.assign(7, 0.0);
  CHECK_FALSE(arm.command(six));
  CHECK_FALSE(arm.command(nan));
  CHECK_FALSE(arm.command(torque));
  CHECK(arm.commands_rejected() == 3);
  CHECK(arm.commands_accepted() == 1);
  CHECK(arm.target() == target);  // never acted on
}

TEST_CASE("gripper: closes on the sheet within the capture distance, carries and releases it", "[world]") {
  twin::SheetSpec spec;
  spec.mesh = twin::make_rectangular_sheet(0.4, 0.3, 0.04);
  spec.placement.origin_m = twin::Vec3(0, 0, 1.0);
  twin::Material m;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 6000;
  m.shear_stiffness_N_m = 2500;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 8e-4;
  m.tensile_viscosity_Ns_m = m.shear_viscosity_Ns_m = 5;
  m.mass_damping_1_s = 1.0;
  const sim_hw::TruthModel model = GENERATE(sim_hw::TruthModel::kIndependent, sim_hw::TruthModel::kTwin);
  INFO("true sheet physics: " << sim_hw::to_string(model));
  sim_hw::TrueSheetOptions options;
  options.model = model;
  sim_hw::TrueSheet sheet(spec, m, options);
  // Loaded at two opposite corners, held 1.4 cm closer together than flat, level.
  std::vector<sim_hw::HeldGrasp> grasps(2);
  grasps[0].clamp = {"A", twin::Vec2(0.02, 0.28), 0.02};
  grasps[0].patch_pose.translation() = twin::Vec3(0.03, 0.27, 1.0);
  grasps[1].clamp = {"B", twin::Vec2(0.38, 0.02), 0.02};
  grasps[1].patch_pose.translation() = twin::Vec3(0.37, 0.03, 1.0);
  grasps[0].jaw_pose = grasps[0].patch_pose;
  grasps[1].jaw_pose = grasps[1].patch_pose;
  REQUIRE(sheet.load(grasps).usable());
  const sim_hw::GripperParameters p{0.03, 0.02, 0.06};
  sim_hw::SimulatedGripper a("A", nullptr, grasps[0].jaw_pose, sheet, p, true);
  sim_hw::SimulatedGripper b("B", nullptr, grasps[1].jaw_pose, sheet, p, true);
  CHECK(a.holding());
  CHECK(b.holding());
  CHECK(sheet.sag_m() > 0.02);

  // A third gripper (operator) 5 mm from the sheet's middle grips; 10 cm away closes on nothing.
  const auto nearest = [&](const twin::Vec2& uv) {
    int best = 0;
    for (int i = 0; i < sheet.mesh().vertex_count(); ++i)
      if ((sheet.mesh().rest_uv[i] - uv).norm() < (sheet.mesh().rest_uv[best] - uv).norm()) best = i;
    return best;
  };
  const auto at = [&](int i) { return twin::Vec3(twin::vertex(sheet.positions(), i)); };
  const int mid = nearest(twin::Vec2(0.2, 0.16)), corner_b = nearest(twin::Vec2(0.4, 0.0));
  Eigen::Isometry3d near = Eigen::Isometry3d::Identity(), far = near;
  near.translation() = at(mid) + twin::Vec3(0, 0.005, 0);
  far.translation() = at(mid) + twin::Vec3(0, 0.10, 0.05);
  sim_hw::SimulatedGripper c("C", nullptr, near, sheet, p, false);
  sim_hw::SimulatedGripper d("D", nullptr, far, sheet, p, false);
  prepreg_lcm::gripper_command_t close{};
  close.action = prepreg_lcm::gripper_command_t::ACTION_CLOSE;
  REQUIRE(c.command(close));
  REQUIRE(d.command(close));
  CHECK(c.holding());
  CHECK_FALSE(d.holding());
  CHECK(d.status(1).state == prepreg_lcm::gripper_status_t::STATE_CLOSED);
  CHECK(d.status(1).width_m == 0.0f);
  CHECK(c.status(1).holding);
  prepreg_lcm::gripper_command_t bad{};
  bad.action = 7;
  CHECK_FALSE(c.command(bad));
  CHECK(c.commands_rejected() == 1);

  // A holding gripper carries its patch: C's point follows its jaw 5 cm up.
  const twin::Vec3 before = at(mid);
  Eigen::Isometry3d up = near;
  up.translation().z() += 0.05;
  sheet.move_jaw("C", up);
  sheet.step(1.0 / 30);
  CHECK((at(mid) - before - twin::Vec3(0, 0, 0.05)).norm() < 0.01);

  // Opening C and B: the sheet hangs from A alone and B's corner swings away from its hold (first
  // up, as the bent sheet springs back, then down; the patch at A holds the sheet level there).
  prepreg_lcm::gripper_command_t open{};
  open.action = prepreg_lcm::gripper_command_t::ACTION_OPEN;
  REQUIRE(c.command(open));
  const twin::Vec3 b_before = at(corner_b);
  REQUIRE(b.command(open));
  CHECK_FALSE(b.holding());
  CHECK_FALSE(c.holding());
  CHECK(a.holding());
  CHECK(b.status(1).state == prepreg_lcm::gripper_status_t::STATE_OPEN);
  CHECK(b.status(1).width_m == Approx(0.06f));
  for (int i = 0; i < 15; ++i) sheet.step(1.0 / 30);
  CHECK(sheet.stats().failures == 0);
  CHECK((at(corner_b) - b_before).norm() > 0.05);
}

TEST_CASE("world config: errors name the file and the field", "[world]") {
  testing_support::TempDir dir("world_config");
  const auto expect_error = [&](const world_test::WorldEdits& edits, const std::string& field) {
    const world_test::WorldFiles f = world_test::make_world_files(dir, edits);
    try {
      sim_hw::WorldConfig c = sim_hw::read_world_config(f.cell, f.world);
      (void)sim_hw::plan_world_start(c);
      FAIL("no error for " << field);
    } catch (const std::exception& e) {
      INFO(e.what());
      CHECK_THAT(e.what(), Catch::Contains(field));
      CHECK_THAT(e.what(), Catch::Contains(".json"));
    }
  };
  world_test::WorldEdits ok;
  const world_test::WorldFiles good = world_test::make_world_files(dir, ok);
  const sim_hw::WorldConfig c = sim_hw::read_world_config(good.cell, good.world);
  CHECK(c.cameras.size() == 3);
  CHECK(c.hardware.arms.size() == 3);
  CHECK(c.plan.grasps.size() == 4);
  CHECK(c.material.tensile_stiffness_u_N_m == 6000);
  CHECK(c.cameras[0].config.backend == "simulated");
  CHECK(c.cameras[0].config.camera_to_cell.translation().x() == Approx(0.001));  // the true pose
  CHECK(c.truth.model == sim_hw::TruthModel::kIndependent);  // a sheet the twin does not share

  world_test::WorldEdits e;
  e.world = [](nlohmann::json& w) { w["cameras"][1]["nois"] = nlohmann::json::object(); };
  expect_error(e, "cameras[1].nois");
  e.world = [](nlohmann::json& w) { w["physics"]["dt_s"] = -1; };
  expect_error(e, "physics.dt_s");
  e.world = [](nlohmann::json& w) { w["cameras"][2]["depth_device"] = "/dev/video9"; };
  expect_error(e, "cameras[2].depth_device");
  e.world = [](nlohmann::json& w) { w["cameras"].erase(2); };
  expect_error(e, "cam_right");
  e.world = [](nlohmann::json& w) { w["cameras"][0]["camera_to_cell"].erase("translation_m"); };
  expect_error(e, "cameras[0].camera_to_cell.translation_m");
  e.world = [](nlohmann::json& w) { w["wind"] = 3; };
  expect_error(e, "wind");
  e.world = [](nlohmann::json& w) { w["physics"]["truth_model"] = "real"; };
  expect_error(e, "physics.truth_model");
  e.world = [](nlohmann::json& w) { w["physics"]["truth_model"] = "spline_shell"; };  // the lab's, not real time
  expect_error(e, "physics.truth_model");
  e.world = [](nlohmann::json& w) { w["physics"]["grid_spacing_m"] = 0; };
  expect_error(e, "physics.grid_spacing_m");
  e.world = nullptr;
  e.plan = [](nlohmann::json& p) { p["grasps"][0]["hold_position_m"] = {-0.4462, -0.3749, 3.5}; };
  expect_error(e, "gripper LEFT");
}
