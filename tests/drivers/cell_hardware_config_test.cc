// The arms and grippers of a cell config, the pose forms (quaternion, rpy, look-at), and the
// example fake cell: every arm reaches its grasp of the example plan.
#include <catch2/catch.hpp>

#include <cmath>

#include "drivers/cell_hardware_config.h"
#include "drivers/iiwa_inverse_kinematics.h"
#include "drivers/json_field.h"
#include "drivers/pose_json.h"
#include "twin/trials/grasp_plan.h"

using namespace drivers;
using nlohmann::json;

namespace {

json two_arms() {
  return json::parse(R"({
    "arms": [
      {"name": "LEFT", "model": "iiwa7", "base_in_cell": {"translation_m": [-0.8, -0.65, 0.5], "rpy_deg": [0, 0, 0]},
       "tool_length_m": 0.15, "home_deg": [0, 30, 0, -90, 0, 60, 0]},
      {"name": "CENTER", "model": "iiwa14", "base_in_cell": {"translation_m": [0.7, 0.75, 0.5], "quaternion_wxyz": [1, 0, 0, 0]}}
    ],
    "grippers": [{"name": "LEFT", "arm": "LEFT"}, {"name": "MANUAL"}]
  })");
}

std::string error_of(const json& doc) {
  try {
    parse_cell_hardware(doc, "cell.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("cell config arms and grippers are read with their models, poses and tools") {
  const CellHardwareConfig c = parse_cell_hardware(two_arms(), "cell.json");
  REQUIRE(c.arms.size() == 2);
  CHECK(c.arms[0].model == IiwaModel::kIiwa7R800);
  CHECK(c.arms[1].model == IiwaModel::kIiwa14R820);
  CHECK(c.arms[0].base_in_cell.translation().isApprox(Eigen::Vector3d(-0.8, -0.65, 0.5)));
  CHECK(c.arms[0].home_rad[3] == Approx(-M_PI / 2));
  CHECK(c.arms[1].tool_length_m == Approx(0.15));  // default
  REQUIRE(c.grippers.size() == 2);
  CHECK(c.find_gripper("MANUAL")->arm.empty());
  CHECK(c.find_arm("CENTER") != nullptr);
  CHECK(c.find_arm("RIGHT") == nullptr);
}

TEST_CASE("cell config hardware errors name the field and what was expected") {
  json d = two_arms();
  d["arms"][1]["model"] = "ur5";
  CHECK_THAT(error_of(d), Catch::Contains("arms[1].model") && Catch::Contains("iiwa14"));
  d = two_arms();
  d["arms"][1]["name"] = "LEFT";
  CHECK_THAT(error_of(d), Catch::Contains("repeats arm 'LEFT'"));
  d = two_arms();
  d["arms"][0]["name"] = "left arm";
  CHECK_THAT(error_of(d), Catch::Contains("arms[0].name") && Catch::Contains("LCM"));
  d = two_arms();
  d["grippers"][1]["arm"] = "RIGHT";
  CHECK_THAT(error_of(d), Catch::Contains("grippers[1].arm") && Catch::Contains("names no arm"));
  d = two_arms();
  d["grippers"][1] = json{{"name", "SECOND"}, {"arm", "LEFT"}};
  CHECK_THAT(error_of(d), Catch::Contains("already carries a gripper"));
  d = two_arms();
  d["arms"][0]["home_deg"][1] = 150;
  CHECK_THAT(error_of(d), Catch::Contains("home_deg") && Catch::Contains("joint limits"));
  d = two_arms();
  d["arms"][0]["reach"] = 1;
  CHECK_THAT(error_of(d), Catch::Contains("reach"));
}

TEST_CASE("a look-at pose points the optical axis at the target with image x horizontal") {
  const json j = json::parse(R"({"translation_m": [0, -1, 1.75], "look_at_m": [0, 0, 0.85]})");
  const Eigen::Isometry3d pose = parse_pose(JsonField(j, "cell.json", "camera_to_cell"));
  const Eigen::Vector3d z = pose.linear().col(2);
  CHECK(z.isApprox(Eigen::Vector3d(0, 1, -0.9).normalized(), 1e-12));
  CHECK(std::abs(pose.linear().col(0).z()) < 1e-12);  // x horizontal
  CHECK(pose.linear().col(1).z() < 0);                // image y points down
  CHECK(pose.linear().determinant() == Approx(1.0));
  const json bad = json::parse(R"({"translation_m": [0, 0, 2], "look_at_m": [0, 0, 1]})");
  CHECK_THROWS_WITH(parse_pose(JsonField(bad, "cell.json", "camera_to_cell")),
                    Catch::Contains("camera_to_cell.look_at_m"));
  const json both = json::parse(R"({"translation_m": [0, 0, 2], "look_at_m": [1, 0, 1], "rpy_deg": [0, 0, 0]})");
  CHECK_THROWS_WITH(parse_pose(JsonField(both, "cell.json", "camera_to_cell")), Catch::Contains("exactly one"));
}

TEST_CASE("the jaw of a gripper reaching down sits tool_length below the flange") {
  const CellHardwareConfig c = parse_cell_hardware(two_arms(), "cell.json");
  const ArmConfig& arm = c.arms[0];
  const Eigen::Vector3d jaw(-0.4, -0.35, 1.0);
  const Eigen::Isometry3d flange = flange_pose_for_jaw(arm, jaw, 0.3);
  CHECK(flange.translation().isApprox(jaw + Eigen::Vector3d(0, 0, 0.15)));
  CHECK(flange.linear().col(2).isApprox(-Eigen::Vector3d::UnitZ()));
  CHECK(jaw_position(arm, flange).isApprox(jaw));
}

TEST_CASE("every arm of the example fake cell reaches its grasp of the example plan") {
  const std::string dir = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/";
  const CellHardwareConfig c = read_cell_hardware(dir + "fake_cell.json");
  const twin::GraspPlan plan = twin::read_grasp_plan(dir + "four_grasp_plan.json");
  int reached = 0;
  for (const twin::Grasp& g : plan.grasps) {
    const GripperConfig* gripper = c.find_gripper(g.gripper);
    REQUIRE(gripper != nullptr);
    if (gripper->arm.empty()) continue;
    const ArmConfig& arm = *c.find_arm(gripper->arm);
    IkOptions options;
    options.restarts = 20;
    const IkResult ik = solve_inverse_kinematics(arm.arm(), flange_pose_for_jaw(arm, g.hold_position_m),
                                                 arm.home_rad, options);
    INFO(g.gripper << ": " << to_string(ik.status) << ", residual " << ik.position_residual_m << " m");
    CHECK(ik.status == IkStatus::kConverged);
    ++reached;
  }
  CHECK(reached == 3);
}
