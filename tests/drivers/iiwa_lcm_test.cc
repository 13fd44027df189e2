// iiwa LCM message <-> joint vector conversions: a command or status made here passes the bus
// checks and round-trips over memq://; malformed ones give no joint vector.
#include <catch2/catch.hpp>

#include <cmath>

#include "drivers/iiwa_lcm.h"
#include "drivers/lcm_bus.h"
#include "drivers/lcm_channels.h"

using namespace drivers;
using namespace std::chrono_literals;

TEST_CASE("an iiwa command round-trips over the bus as a joint vector", "[iiwa_lcm]") {
  LcmBus bus("memq://");
  JointVector q;
  q << 0.1, -0.2, 0.3, -1.4, 0.5, 0.6, -0.7;
  std::optional<JointVector> received;
  bus.subscribe<lcmt_iiwa_command>(channels::iiwa_command(channels::kArmRight),
                                   [&](const lcmt_iiwa_command& m) {
                                     received = commanded_positions(m);
                                   });
  REQUIRE(bus.publish(channels::iiwa_command(channels::kArmRight), make_iiwa_command(5, q)));
  bus.handle_for(100ms);
  REQUIRE(received.has_value());
  CHECK(*received == q);
}

TEST_CASE("an iiwa status carries measured, velocity and commanded joints", "[iiwa_lcm]") {
  JointVector measured = JointVector::LinSpaced(-0.3, 0.3);
  JointVector velocity = JointVector::Constant(0.05);
  JointVector commanded = measured + JointVector::Constant(0.01);
  const lcmt_iiwa_status m = make_iiwa_status(9, measured, velocity, commanded);
  CHECK(message_problem(m).empty());
  REQUIRE(measured_positions(m).has_value());
  CHECK(*measured_positions(m) == measured);
  CHECK(m.joint_velocity_estimated[6] == 0.05);
  CHECK(m.joint_position_commanded[0] == Approx(-0.29));
}

TEST_CASE("malformed iiwa messages give no joint vector", "[iiwa_lcm]") {
  lcmt_iiwa_command command = make_iiwa_command(1, JointVector::Zero());
  REQUIRE(commanded_positions(command).has_value());
  auto six = command;
  six.num_joints = 6;
  six.joint_position.pop_back();
  CHECK_FALSE(commanded_positions(six).has_value());
  auto torque = command;
  torque.num_torques = 7;
  torque.joint_torque.assign(7, 0.0);
  CHECK_FALSE(commanded_positions(torque).has_value());
  auto nan = command;
  nan.joint_position[2] = std::nan("");
  CHECK_FALSE(commanded_positions(nan).has_value());

  lcmt_iiwa_status status = make_iiwa_status(1, JointVector::Zero(), JointVector::Zero(),
                                             JointVector::Zero());
  status.num_joints = 0;
  CHECK_FALSE(measured_positions(status).has_value());
}
