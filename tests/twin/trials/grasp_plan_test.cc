// The grasp plan file: round trip, defaults, and errors that name the field.
#include <catch2/catch.hpp>

#include "tests/support/temp_dir.h"
#include "twin/trials/grasp_plan.h"

using namespace twin;
using nlohmann::json;

namespace {

json plan_json() {
  return json::parse(R"({"grasps": [
      {"gripper": "LEFT", "material_point_m": [0.1, 0.08], "hold_position_m": [-0.45, -0.37, 1.0]},
      {"gripper": "MANUAL", "material_point_m": [0.15, 0.88], "grip_radius_m": 0.03, "hold_position_m": [-0.4, 0.36, 1.0]}],
    "predicted_sag_m": 0.12, "note": "test"})");
}

}  // namespace

TEST_CASE("a grasp plan round-trips through its file") {
  const GraspPlan plan = grasp_plan_from_json(plan_json(), "plan.json");
  REQUIRE(plan.grasps.size() == 2);
  CHECK(plan.grasps[0].clamp.id == "LEFT");
  CHECK(plan.grasps[0].clamp.grip_radius_m == Approx(kDefaultGripRadiusM));
  CHECK(plan.grasps[1].clamp.grip_radius_m == Approx(0.03));
  CHECK(plan.feasible);
  CHECK(plan.index_of("MANUAL") == 1);
  CHECK(plan.index_of("RIGHT") == -1);
  testing_support::TempDir dir("grasp_plan");
  const std::string path = (dir / "plan.json").string();
  write_grasp_plan(plan, path);
  const GraspPlan back = read_grasp_plan(path);
  REQUIRE(back.grasps.size() == 2);
  CHECK(back.grasps[1].hold_position_m.isApprox(plan.grasps[1].hold_position_m));
  CHECK(back.grasps[1].clamp.material_point_m.isApprox(plan.grasps[1].clamp.material_point_m));
  CHECK(back.predicted_sag_m == Approx(0.12));
  CHECK(back.note == "test");
}

TEST_CASE("grasp plan errors name the field") {
  json j = plan_json();
  j["grasps"][1]["gripper"] = "LEFT";
  CHECK_THROWS_WITH(grasp_plan_from_json(j, "plan.json"), Catch::Contains("grasps[1].gripper") && Catch::Contains("repeats"));
  j = plan_json();
  j["grasps"][0].erase("hold_position_m");
  CHECK_THROWS_WITH(grasp_plan_from_json(j, "plan.json"), Catch::Contains("grasps[0].hold_position_m"));
  j = plan_json();
  j["grasps"] = json::array();
  CHECK_THROWS_WITH(grasp_plan_from_json(j, "plan.json"), Catch::Contains("at least one grasp"));
  j = plan_json();
  j["grasps"][0]["grip_radius_m"] = -0.01;
  CHECK_THROWS_WITH(grasp_plan_from_json(j, "plan.json"), Catch::Contains("grip_radius_m"));
  j = plan_json();
  j["feasable"] = true;
  CHECK_THROWS_WITH(grasp_plan_from_json(j, "plan.json"), Catch::Contains("feasable"));
}
