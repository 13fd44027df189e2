// drivers::message_problem: each message type accepts a well-formed example and names what is
// wrong in a malformed or out-of-range one.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "drivers/lcm_message_checks.h"

using drivers::message_problem;
using Catch::Contains;

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}

TEST_CASE("sheet state checks", "[lcm_checks]") {
  prepreg_lcm::sheet_state_t m{};
  m.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  m.num_vertices = 3;
  m.x_m = {0, 1, 2};
  m.y_m = {0, 0, 0};
  m.z_m = {1, 1, kNaN};  // vertex 2 unseen: its position may be unknown
  m.num_observed_flags = 3;
  m.vertex_observed = {true, true, false};
  m.coverage = 2.0f / 3;
  CHECK(message_problem(m).empty());

  auto bad = m;
  bad.vertex_observed[2] = true;
  CHECK_THAT(message_problem(bad), Contains("vertex 2"));
  bad = m;
  bad.num_observed_flags = 2;
  bad.vertex_observed.pop_back();
  CHECK_THAT(message_problem(bad), Contains("num_observed_flags"));
  bad = m;
  bad.coverage = 1.5f;
  CHECK_THAT(message_problem(bad), Contains("coverage"));
  bad = m;
  bad.source = 0;
  CHECK_THAT(message_problem(bad), Contains("source"));
  bad = m;
  bad.num_vertices = -1;
  CHECK_THAT(message_problem(bad), Contains("count -1"));
}

TEST_CASE("prediction error checks", "[lcm_checks]") {
  prepreg_lcm::prediction_error_t m{};
  m.num_compared = 100;
  m.mean_m = 0.01f;
  m.max_m = 0.03f;
  m.score_m = 0.01f + 0.5f * 0.03f;
  m.num_vertex_errors = 2;
  m.vertex_error_m = {0.02f, kNaN};
  CHECK(message_problem(m).empty());

  auto bad = m;
  bad.score_m = 0.04f;
  CHECK_THAT(message_problem(bad), Contains("score_m"));
  bad = m;
  bad.mean_m = 0.05f;
  bad.score_m = 0.05f + 0.015f;
  CHECK_THAT(message_problem(bad), Contains("exceeds max_m"));
  bad = m;
  bad.vertex_error_m[0] = -0.1f;
  CHECK_THAT(message_problem(bad), Contains("vertex_error_m[0]"));
  bad = m;
  bad.max_m = kNaN;
  CHECK_THAT(message_problem(bad), Contains("max_m"));
  // Times from 0 to 2^53 us, so that the monitor's latency (utime - frames_utime) cannot
  // overflow (found by fuzzing: frames_utime near -2^63).
  bad = m;
  bad.frames_utime = std::numeric_limits<std::int64_t>::min() + 1;
  CHECK_THAT(message_problem(bad), Contains("frames_utime"));
  bad = m;
  bad.utime = std::int64_t{1} << 60;
  CHECK_THAT(message_problem(bad), Contains("utime"));
}

TEST_CASE("camera, cell and gripper state checks", "[lcm_checks]") {
  prepreg_lcm::camera_status_t camera{};
  camera.name = "LEFT";
  camera.state = prepreg_lcm::camera_status_t::STATE_LOST;
  CHECK(message_problem(camera).empty());
  camera.state = 5;
  CHECK_THAT(message_problem(camera), Contains("state = 5"));
  camera.state = 2;
  camera.name.clear();
  CHECK_THAT(message_problem(camera), Contains("name"));

  prepreg_lcm::cell_state_t cell{};
  cell.state = prepreg_lcm::cell_state_t::STATE_SAFE_HOLD;
  cell.num_cameras = 3;
  cell.num_cameras_ok = 0;
  CHECK(message_problem(cell).empty());
  cell.num_cameras_ok = 4;
  CHECK_THAT(message_problem(cell), Contains("num_cameras_ok"));

  prepreg_lcm::gripper_command_t command{};
  command.action = prepreg_lcm::gripper_command_t::ACTION_CLOSE;
  command.force_n = 40;
  CHECK(message_problem(command).empty());
  command.action = 2;
  CHECK_THAT(message_problem(command), Contains("action"));
  command.action = 0;
  command.width_m = -0.01f;
  CHECK_THAT(message_problem(command), Contains("width_m"));

  prepreg_lcm::gripper_status_t status{};
  status.state = prepreg_lcm::gripper_status_t::STATE_FAULT;
  CHECK(message_problem(status).empty());
  status.state = -1;
  CHECK_THAT(message_problem(status), Contains("state"));
}

TEST_CASE("grasp plan checks", "[lcm_checks]") {
  prepreg_lcm::grasp_plan_t m{};
  m.num_grasps = 2;
  m.material_u_m = {0.1f, 1.0f};
  m.material_v_m = {0.05f, 0.05f};
  m.cell_x_m = {0.3f, 1.2f};
  m.cell_y_m = {0.0f, 0.0f};
  m.cell_z_m = {1.1f, 1.1f};
  m.arm = {"LEFT", "RIGHT"};
  m.predicted_sag_m = 0.12f;
  CHECK(message_problem(m).empty());

  auto bad = m;
  bad.arm[1].clear();
  CHECK_THAT(message_problem(bad), Contains("arm[1]"));
  bad = m;
  bad.cell_z_m.pop_back();
  CHECK_THAT(message_problem(bad), Contains("cell_z_m"));
  bad = m;
  bad.material_u_m[0] = kNaN;
  CHECK_THAT(message_problem(bad), Contains("material_u_m[0]"));
  bad = m;
  bad.num_grasps = 17;
  CHECK_THAT(message_problem(bad), Contains("outside [0, 16]"));
}

TEST_CASE("iiwa status checks", "[lcm_checks]") {
  lcmt_iiwa_status m{};
  m.num_joints = 7;
  for (auto* v : {&m.joint_position_measured, &m.joint_velocity_estimated,
                  &m.joint_position_commanded, &m.joint_position_ipo, &m.joint_torque_measured,
                  &m.joint_torque_commanded, &m.joint_torque_external}) {
    v->assign(7, 0.1);
  }
  m.joint_position_ipo.assign(7, std::nan(""));  // FRI gives no ipo positions when monitoring
  CHECK(message_problem(m).empty());

  auto bad = m;
  bad.joint_torque_external.pop_back();
  CHECK_THAT(message_problem(bad), Contains("joint_torque_external"));
  bad = m;
  bad.joint_position_measured[6] = std::numeric_limits<double>::infinity();
  CHECK_THAT(message_problem(bad), Contains("joint_position_measured[6]"));
  bad = m;
  bad.num_joints = 8;
  CHECK_THAT(message_problem(bad), Contains("outside [0, 7]"));
}

TEST_CASE("diagnosis checks", "[lcm_checks]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  prepreg_lcm::diagnosis_t m{};
  m.verdict = "unexplained";
  m.effect = "clamp_grip";  // the closest candidate
  m.adoption = "not named";
  m.noise_sigma_m = 0.002;
  m.base_fitted_mean_m = 0.009;
  m.base_held_out_mean_m = 0.012;
  m.effect_fitted_mean_m = nan;  // not refitted
  m.effect_held_out_mean_m = nan;
  m.num_parameters = 1;
  m.parameter_names = {"clamp_grip_strength"};
  m.values = {0.4};
  m.lower95 = {0.2};
  m.upper95 = {0.7};
  m.held_out_error_before_m = nan;
  m.held_out_error_after_m = nan;
  m.states = 3;
  CHECK(message_problem(m).empty());

  auto bad = m;
  bad.verdict = "maybe";
  CHECK_THAT(message_problem(bad), Contains("verdict 'maybe'"));
  bad = m;
  bad.adoption = "adopted";
  CHECK_THAT(message_problem(bad), Contains("without verdict 'effect'"));
  bad = m;
  bad.adoption = "kept";
  CHECK_THAT(message_problem(bad), Contains("adoption 'kept'"));
  bad = m;
  bad.values = {0.9};
  CHECK_THAT(message_problem(bad), Contains("outside its interval"));
  bad = m;
  bad.num_parameters = 2;
  CHECK_THAT(message_problem(bad), Contains("parameter_names"));
  bad = m;
  bad.base_held_out_mean_m = -1.0;
  CHECK_THAT(message_problem(bad), Contains("base_held_out_mean_m"));
  bad = m;
  bad.seconds = -1.0;
  CHECK_THAT(message_problem(bad), Contains("seconds"));
}
