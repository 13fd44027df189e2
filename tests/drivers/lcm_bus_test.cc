// LcmBus on the in-process memq:// provider: typed round trips, regex subscriptions, and the
// real-time rule that malformed or out-of-range messages are dropped and counted, never thrown
// and never handed to a callback.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/lcm_bus.h"
#include "drivers/lcm_channels.h"

using drivers::HandleResult;
using drivers::LcmBus;
using namespace std::chrono_literals;
namespace channels = drivers::channels;

namespace {

prepreg_lcm::sheet_state_t observed_sheet(int vertices) {
  prepreg_lcm::sheet_state_t msg;
  msg.utime = 1'700'000'000'000'000;
  msg.cycle_id = 17;
  msg.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  msg.num_vertices = vertices;
  msg.num_observed_flags = vertices;
  for (int i = 0; i < vertices; ++i) {
    msg.x_m.push_back(0.01f * i);
    msg.y_m.push_back(-0.02f * i);
    msg.z_m.push_back(1.0f + 0.001f * i);
    msg.vertex_observed.push_back(i % 3 != 0);
  }
  msg.coverage = 0.66f;
  return msg;
}

prepreg_lcm::cell_state_t cell_state(int8_t state) {
  prepreg_lcm::cell_state_t msg{};
  msg.utime = drivers::utime_now();
  msg.cycle_id = 3;
  msg.state = state;
  msg.reason = "camera RIGHT stale for 0.5 s";
  msg.num_cameras = 3;
  msg.num_cameras_ok = 2;
  return msg;
}

template <typename T>
std::vector<std::uint8_t> encode(const T& msg) {
  std::vector<std::uint8_t> bytes(msg.getEncodedSize());
  REQUIRE(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == int(bytes.size()));
  return bytes;
}

}  // namespace

TEST_CASE("a sheet state published on memq:// arrives decoded and equal", "[lcm_bus]") {
  LcmBus bus("memq://");
  std::vector<prepreg_lcm::sheet_state_t> received;
  const auto id = bus.subscribe<prepreg_lcm::sheet_state_t>(
      std::string(channels::kSheetObserved),
      [&](const prepreg_lcm::sheet_state_t& msg) { received.push_back(msg); });

  const auto sent = observed_sheet(500);
  REQUIRE(bus.publish(std::string(channels::kSheetObserved), sent));
  // Another channel is not delivered to this subscription.
  REQUIRE(bus.publish(std::string(channels::kSheetPredicted), sent));
  const HandleResult result = bus.handle_for(100ms);
  CHECK(result.status == HandleResult::Status::kHandled);

  REQUIRE(received.size() == 1);
  const auto& got = received[0];
  CHECK(got.utime == sent.utime);
  CHECK(got.cycle_id == 17);
  CHECK(got.x_m == sent.x_m);
  CHECK(got.y_m == sent.y_m);
  CHECK(got.z_m == sent.z_m);
  CHECK(got.vertex_observed == sent.vertex_observed);
  CHECK(got.coverage == sent.coverage);
  CHECK(bus.counters(id).delivered == 1);
  CHECK(bus.counters().decode_failures == 0);
}

TEST_CASE("handle_for times out without messages and reports it", "[lcm_bus]") {
  LcmBus bus("memq://");
  int calls = 0;
  bus.subscribe<prepreg_lcm::cell_state_t>("CELL_STATE",
                                           [&](const prepreg_lcm::cell_state_t&) { ++calls; });
  const auto start = std::chrono::steady_clock::now();
  const HandleResult result = bus.handle_for(20ms);
  const auto waited = std::chrono::steady_clock::now() - start;
  CHECK(result.status == HandleResult::Status::kTimeout);
  CHECK(result.messages == 0);
  CHECK(waited >= 15ms);
  CHECK(calls == 0);
}

TEST_CASE("handle_for dispatches every waiting message in one call", "[lcm_bus]") {
  LcmBus bus("memq://");
  std::vector<std::int64_t> cycles;
  bus.subscribe<prepreg_lcm::cell_state_t>(
      "CELL_STATE", [&](const prepreg_lcm::cell_state_t& m) { cycles.push_back(m.cycle_id); });
  for (int i = 0; i < 5; ++i) {
    auto msg = cell_state(prepreg_lcm::cell_state_t::STATE_RUNNING);
    msg.cycle_id = i;
    REQUIRE(bus.publish("CELL_STATE", msg));
  }
  const HandleResult result = bus.handle_for(100ms);
  CHECK(result.messages == 5);
  CHECK(cycles == std::vector<std::int64_t>{0, 1, 2, 3, 4});
}

TEST_CASE("a message of another type is counted as a decode failure, not delivered",
          "[lcm_bus]") {
  LcmBus bus("memq://");
  int calls = 0;
  const auto id = bus.subscribe<prepreg_lcm::cell_state_t>(
      "CELL_STATE", [&](const prepreg_lcm::cell_state_t&) { ++calls; });

  prepreg_lcm::camera_status_t wrong_type{};
  wrong_type.name = "LEFT";
  REQUIRE(bus.publish("CELL_STATE", wrong_type));
  // A valid message cut short, and one with bytes after its end.
  auto bytes = encode(cell_state(prepreg_lcm::cell_state_t::STATE_READY));
  REQUIRE(bus.publish_raw("CELL_STATE", bytes.data(), bytes.size() - 3));
  bytes.push_back(0);
  REQUIRE(bus.publish_raw("CELL_STATE", bytes.data(), bytes.size()));
  REQUIRE(bus.publish_raw("CELL_STATE", bytes.data(), 0));

  HandleResult result;
  REQUIRE_NOTHROW(result = bus.handle_for(100ms));
  CHECK(result.messages == 4);
  CHECK(calls == 0);
  CHECK(bus.counters(id).decode_failures == 4);
  CHECK(bus.counters().decode_failures == 4);
  CHECK(bus.counters().delivered == 0);
  CHECK_THAT(bus.last_problem(), Catch::Contains("CELL_STATE"));
}

TEST_CASE("an out-of-range message is rejected and counted, never acted on", "[lcm_bus]") {
  LcmBus bus("memq://");
  int calls = 0;
  bus.subscribe<prepreg_lcm::cell_state_t>("CELL_STATE",
                                           [&](const prepreg_lcm::cell_state_t&) { ++calls; });
  // publish() refuses it, so send its bytes the way a foreign process would.
  const auto bad = cell_state(42);
  CHECK_FALSE(bus.publish("CELL_STATE", bad));
  CHECK(bus.counters().publish_failures == 1);
  CHECK_THAT(bus.last_problem(), Catch::Contains("state = 42"));
  const auto bytes = encode(bad);
  REQUIRE(bus.publish_raw("CELL_STATE", bytes.data(), bytes.size()));
  REQUIRE(bus.publish("CELL_STATE", cell_state(prepreg_lcm::cell_state_t::STATE_DEGRADED)));

  bus.handle_for(100ms);
  CHECK(calls == 1);
  CHECK(bus.counters().rejected == 1);
  CHECK(bus.counters().delivered == 1);
}

TEST_CASE("publish refuses a message whose counts disagree with its arrays", "[lcm_bus]") {
  LcmBus bus("memq://");
  auto msg = observed_sheet(10);
  msg.num_vertices = 11;  // LCM's encoder would read past the vectors
  CHECK_FALSE(bus.publish("SHEET_OBSERVED", msg));
  CHECK_THAT(bus.last_problem(), Catch::Contains("x_m"));

  lcmt_iiwa_command command{};
  command.num_joints = 7;
  command.joint_position.assign(7, 0.0);
  command.joint_position[3] = std::nan("");
  CHECK_FALSE(bus.publish("IIWA_COMMAND_LEFT", command));
  command.joint_position[3] = 0.5;
  CHECK(bus.publish("IIWA_COMMAND_LEFT", command));
  CHECK(bus.counters().publish_failures == 2);
}

TEST_CASE("an exception from a callback is caught and counted", "[lcm_bus]") {
  LcmBus bus("memq://");
  bus.subscribe<prepreg_lcm::cell_state_t>("CELL_STATE", [](const prepreg_lcm::cell_state_t&) {
    throw std::runtime_error("planner crashed");
  });
  REQUIRE(bus.publish("CELL_STATE", cell_state(prepreg_lcm::cell_state_t::STATE_RUNNING)));
  HandleResult result;
  REQUIRE_NOTHROW(result = bus.handle_for(100ms));
  CHECK(result.status == HandleResult::Status::kHandled);
  CHECK(bus.counters().callback_errors == 1);
  CHECK_THAT(bus.last_problem(), Catch::Contains("planner crashed"));
}

TEST_CASE("a regex subscription receives every camera's status with its channel",
          "[lcm_bus]") {
  LcmBus bus("memq://");
  std::vector<std::string> seen;
  bus.subscribe_with_channel<prepreg_lcm::camera_status_t>(
      std::string(channels::kCameraStatusPrefix) + ".*",
      [&](const std::string& channel, const prepreg_lcm::camera_status_t& msg) {
        seen.push_back(channel + "=" + msg.name);
      });
  for (const char* name : {"left", "right", "top"}) {
    prepreg_lcm::camera_status_t msg{};
    msg.name = name;
    msg.state = prepreg_lcm::camera_status_t::STATE_ACTIVE;
    REQUIRE(bus.publish(channels::camera_status(name), msg));
  }
  bus.handle_for(100ms);
  CHECK(seen == std::vector<std::string>{"CAMERA_STATUS_LEFT=left", "CAMERA_STATUS_RIGHT=right",
                                         "CAMERA_STATUS_TOP=top"});
}

TEST_CASE("unsubscribe stops delivery", "[lcm_bus]") {
  LcmBus bus("memq://");
  int calls = 0;
  const auto id = bus.subscribe<prepreg_lcm::gripper_status_t>(
      "GRIPPER_STATUS_LEFT", [&](const prepreg_lcm::gripper_status_t&) { ++calls; });
  prepreg_lcm::gripper_status_t msg{};
  msg.state = prepreg_lcm::gripper_status_t::STATE_CLOSED;
  msg.holding = true;
  REQUIRE(bus.publish("GRIPPER_STATUS_LEFT", msg));
  bus.handle_for(100ms);
  bus.unsubscribe(id);
  REQUIRE(bus.publish("GRIPPER_STATUS_LEFT", msg));
  bus.handle_for(20ms);
  CHECK(calls == 1);
}

TEST_CASE("a callback may unsubscribe, nothing more reaches it", "[lcm_bus]") {
  LcmBus bus("memq://");
  int first_calls = 0, second_calls = 0;
  LcmBus::SubscriptionId second = 0;
  const LcmBus::SubscriptionId first = bus.subscribe<prepreg_lcm::gripper_status_t>(
      "GRIPPER_STATUS_LEFT", [&](const prepreg_lcm::gripper_status_t&) {
        ++first_calls;
        bus.unsubscribe(first);
        bus.unsubscribe(second);
      });
  second = bus.subscribe<prepreg_lcm::gripper_status_t>(
      "GRIPPER_STATUS_LEFT", [&](const prepreg_lcm::gripper_status_t&) { ++second_calls; });
  prepreg_lcm::gripper_status_t msg{};
  for (int i = 0; i < 3; ++i) REQUIRE(bus.publish("GRIPPER_STATUS_LEFT", msg));
  bus.handle_for(100ms);
  bus.handle_for(10ms);
  CHECK(first_calls == 1);
  // Three messages were sent; the second subscription may have seen the first one only if LCM
  // ran its handler before the first subscription's.
  CHECK(second_calls <= 1);
  CHECK(bus.counters().delivered == std::uint64_t(1 + second_calls));
}

TEST_CASE("a bad LCM URL is an error naming the URL", "[lcm_bus]") {
  CHECK_THROWS_WITH(LcmBus("nonsense://nowhere"), Catch::Contains("nonsense://nowhere"));
  CHECK_THROWS_WITH(LcmBus("udpm://not.an.address:7667"),
                    Catch::Contains("udpm://not.an.address:7667"));
}

TEST_CASE("per-device channel names follow the upper-case suffix convention", "[lcm_bus]") {
  CHECK(channels::iiwa_command(channels::kArmLeft) == "IIWA_COMMAND_LEFT");
  CHECK(channels::iiwa_status("center") == "IIWA_STATUS_CENTER");
  CHECK(channels::gripper_command("right") == "GRIPPER_COMMAND_RIGHT");
  CHECK(channels::gripper_status("Right_2") == "GRIPPER_STATUS_RIGHT_2");
  CHECK(channels::camera_status("d415_a") == "CAMERA_STATUS_D415_A");
  CHECK_THROWS_WITH(channels::camera_status("left cam"), Catch::Contains("'left cam'"));
  CHECK_THROWS_AS(channels::iiwa_command(""), std::invalid_argument);
}
