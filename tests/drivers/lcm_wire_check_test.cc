// The layouts that check encoded LCM messages before lcm-gen's decode allocates their arrays
// (drivers/lcm_wire_check.h): every type of drivers/lcmtypes walks exactly, counts that cannot
// fit are refused naming the field, and the bus drops such a message without allocating it.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <lcmt_iiwa_command.hpp>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/calibration_t.hpp>
#include <prepreg_lcm/camera_status_t.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/diagnosis_t.hpp>
#include <prepreg_lcm/grasp_plan_t.hpp>
#include <prepreg_lcm/gripper_command_t.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>
#include <prepreg_lcm/sim_fault_t.hpp>

#include "drivers/lcm_bus.h"
#include "drivers/lcm_wire_check.h"

namespace {

template <typename T>
std::vector<std::uint8_t> encoded(const T& msg) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  REQUIRE(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == static_cast<int>(bytes.size()));
  return bytes;
}

// The layout walks the encoded message exactly; one byte less or more is refused.
template <typename T>
void check_walks_exactly(const T& msg) {
  INFO(T::getTypeName());
  REQUIRE(drivers::has_wire_layout(T::getTypeName()));
  std::vector<std::uint8_t> bytes = encoded(msg);
  CHECK(drivers::wire_problem(T::getTypeName(), bytes.data(), static_cast<int>(bytes.size())).empty());
  CHECK_FALSE(drivers::wire_problem(T::getTypeName(), bytes.data(), static_cast<int>(bytes.size()) - 1).empty());
  bytes.push_back(0);
  CHECK_FALSE(drivers::wire_problem(T::getTypeName(), bytes.data(), static_cast<int>(bytes.size())).empty());
}

void put_int32(std::vector<std::uint8_t>& bytes, std::size_t at, std::int32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(v) >> (24 - 8 * i));
}

prepreg_lcm::sheet_state_t sheet(int n) {
  prepreg_lcm::sheet_state_t s{};
  s.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  s.num_vertices = n;
  s.x_m.assign(n, 0.1f);
  s.y_m.assign(n, 0.2f);
  s.z_m.assign(n, 1.0f);
  s.num_observed_flags = n;
  s.vertex_observed.assign(n, true);
  s.coverage = 1.0f;
  return s;
}

}  // namespace

TEST_CASE("every message type's wire layout walks its encoding exactly", "[lcm_bus][wire]") {
  check_walks_exactly(sheet(5));
  prepreg_lcm::prediction_error_t e{};
  e.num_vertex_errors = 3;
  e.vertex_error_m.assign(3, 0.01f);
  check_walks_exactly(e);
  prepreg_lcm::cell_state_t c{};
  c.reason = "camera cam_left lost";
  check_walks_exactly(c);
  prepreg_lcm::camera_status_t cam{};
  cam.name = "cam_left";
  cam.message = "";
  check_walks_exactly(cam);
  check_walks_exactly(prepreg_lcm::gripper_status_t{});
  check_walks_exactly(prepreg_lcm::gripper_command_t{});
  prepreg_lcm::sim_fault_t f{};
  f.target = "twin";
  f.fault = "diverge";
  check_walks_exactly(f);
  prepreg_lcm::sim_clock_t clock{};
  clock.held_by = "cell_controller";
  check_walks_exactly(clock);
  prepreg_lcm::sim_clock_hold_t hold{};
  hold.client = "cell_controller";
  check_walks_exactly(hold);
  prepreg_lcm::grasp_plan_t g{};
  g.num_grasps = 2;
  for (auto* v : {&g.material_u_m, &g.material_v_m, &g.cell_x_m, &g.cell_y_m, &g.cell_z_m}) v->assign(2, 0.5f);
  g.arm = {"LEFT", "MANUAL"};
  g.note = "four grasps";
  check_walks_exactly(g);
  prepreg_lcm::calibration_t cal{};
  cal.verdict = "adopted";
  cal.num_parameters = 2;
  cal.parameter_names = {"a", "bb"};
  cal.values = cal.lower95 = cal.upper95 = {1.0, 2.0};
  cal.determined = {true, false};
  cal.material_file = "m.json";
  check_walks_exactly(cal);
  prepreg_lcm::diagnosis_t d{};
  d.verdict = "effect";
  d.num_parameters = 1;
  d.parameter_names = {"clamp_grip_strength"};
  d.values = d.lower95 = d.upper95 = {0.1};
  check_walks_exactly(d);
  lcmt_iiwa_command cmd{};
  cmd.num_joints = 7;
  cmd.joint_position.assign(7, 0.1);
  cmd.num_torques = 0;
  check_walks_exactly(cmd);
  lcmt_iiwa_status st{};
  st.num_joints = 7;
  for (auto* v : {&st.joint_position_measured, &st.joint_velocity_estimated, &st.joint_position_commanded,
                  &st.joint_position_ipo, &st.joint_torque_measured, &st.joint_torque_commanded,
                  &st.joint_torque_external}) {
    v->assign(7, 0.1);
  }
  check_walks_exactly(st);
}

TEST_CASE("array counts that cannot fit in the message are refused naming the count", "[lcm_bus][wire]") {
  // sheet_state_t: fingerprint (8), utime (8), cycle_id (8), source (1), then num_vertices.
  std::vector<std::uint8_t> bytes = encoded(sheet(2));
  put_int32(bytes, 25, 2147483647);
  const std::string problem = drivers::wire_problem("sheet_state_t", bytes.data(), static_cast<int>(bytes.size()));
  CHECK_THAT(problem, Catch::Contains("num_vertices 2147483647 needs") && Catch::Contains("x_m"));
  put_int32(bytes, 25, -3);  // found by fuzzing: the decode threw std::length_error
  CHECK_THAT(drivers::wire_problem("sheet_state_t", bytes.data(), static_cast<int>(bytes.size())),
             Catch::Contains("num_vertices -3 is negative"));
  // A string array: the count alone needs four bytes per string.
  prepreg_lcm::diagnosis_t d{};
  std::vector<std::uint8_t> diag = encoded(d);
  // fingerprint, utime, diagnosis_id (24), four empty strings (4 x 5), five doubles (40).
  put_int32(diag, 24 + 20 + 40, 100000000);
  CHECK_THAT(drivers::wire_problem("diagnosis_t", diag.data(), static_cast<int>(diag.size())),
             Catch::Contains("num_parameters 100000000 needs at least"));
  // A scalar string cut off before its length (found by fuzzing this check itself).
  prepreg_lcm::sim_fault_t f{};
  std::vector<std::uint8_t> fault = encoded(f);
  CHECK_THAT(drivers::wire_problem("sim_fault_t", fault.data(), 8 + 8 + 2), Catch::Contains("string target is cut off"));
  CHECK_THROWS_AS(drivers::wire_problem("no_such_t", bytes.data(), 8), std::logic_error);
}

TEST_CASE("the bus drops a small message claiming a huge array before decoding it", "[lcm_bus][wire]") {
  // Found by fuzzing (tests/fuzz lcm_monitor): lcm-gen's decode allocated 2^31 floats (8 GB) for
  // a 30-byte message before it found the bytes missing.
  drivers::LcmBus bus("memq://");
  int delivered = 0;
  bus.subscribe<prepreg_lcm::sheet_state_t>("SHEET_OBSERVED",
                                            [&](const prepreg_lcm::sheet_state_t&) { ++delivered; });
  std::vector<std::uint8_t> bytes = encoded(sheet(0));
  put_int32(bytes, 25, 2147483647);
  bus.publish_raw("SHEET_OBSERVED", bytes.data(), bytes.size());
  bus.handle_for(std::chrono::milliseconds(100));
  CHECK(delivered == 0);
  CHECK(bus.counters().decode_failures == 1);
  CHECK_THAT(bus.last_problem(), Catch::Contains("num_vertices 2147483647 needs"));
}
