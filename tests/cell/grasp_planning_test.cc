// Grasp planning with the twin (cell/grasp_planning): goal file, hang metrics, reachability,
// the planner on the composite ply (coarse meshes so each case stays well under 10 s).
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include "cell/grasp_planning/grasp_assignment.h"
#include "cell/grasp_planning/grasp_planner.h"
#include "cell/grasp_planning/hang_evaluation_codec.h"
#include "tests/support/temp_dir.h"

namespace {

const std::string kExamples = std::string(PREPREG_SOURCE_DIR) + "/cell/examples";

// The example goal on coarse meshes with a small search.
nlohmann::json test_goal_json() {
  return nlohmann::json::parse(R"({
    "sheet": {"width_m": 1.17, "height_m": 0.975, "target_triangles": 500},
    "material_file": "composite_identified.json",
    "tool": {"centre_m": [0.0, 0.0], "top_z_m": 0.70, "size_m": [1.3, 1.1]},
    "hold_z_m": 1.0,
    "max_sag_m": 0.25,
    "min_clearance_m": 0.05,
    "folds": {"min_bend_radius_m": 0.02, "max_overturned_fraction": 0.0},
    "grippers": ["LEFT", "RIGHT", "CENTER", "MANUAL"],
    "search": {"inset_m": [0.08, 0.15], "ring_spacing_m": 0.15, "slack_factors": [0.04, 0.08],
               "random_candidates": 2, "screening_triangles": 250, "finalists": 2, "seed": 3}
  })");
}

cell::GraspGoal goal_from(const nlohmann::json& j) {
  return cell::grasp_goal_from_json(j, "goal.json", kExamples);
}

std::string error_of(const nlohmann::json& j) {
  try {
    goal_from(j);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("goal file errors name the file and the field", "[grasp_planning]") {
  CHECK_NOTHROW(goal_from(test_goal_json()));
  auto broken = [](const char* pointer, const nlohmann::json& value) {
    nlohmann::json j = test_goal_json();
    j[nlohmann::json::json_pointer(pointer)] = value;
    return error_of(j);
  };
  CHECK_THAT(broken("/max_sag_m", -0.1), Catch::Contains("goal.json") && Catch::Contains("'max_sag_m'"));
  CHECK_THAT(broken("/grippers", {"LEFT"}), Catch::Contains("'grippers'") && Catch::Contains("2 to 4"));
  CHECK_THAT(broken("/grippers", {"A", "A"}), Catch::Contains("'grippers[1]'"));
  CHECK_THAT(broken("/tool/top_z_m", "high"), Catch::Contains("'tool.top_z_m'"));
  CHECK_THAT(broken("/hold_z_m", 0.5), Catch::Contains("'hold_z_m'") && Catch::Contains("above"));
  CHECK_THAT(broken("/search/slack_factors", {0.7}), Catch::Contains("'search.slack_factors[0]'"));
  CHECK_THAT(broken("/folds/max_overturned_fraction", 2.0), Catch::Contains("'folds.max_overturned_fraction'"));
  CHECK_THAT(broken("/sheet/width_m", 0), Catch::Contains("'sheet.width_m'"));
  CHECK_THAT(broken("/search/finalists", "some"), Catch::Contains("'search.finalists'") && Catch::Contains("\"all\""));
  CHECK_THAT(broken("/search/finalists", 0), Catch::Contains("'search.finalists'"));
  nlohmann::json all = test_goal_json();
  all["search"]["finalists"] = "all";
  CHECK(goal_from(all).search.finalists == 0);
  all["search"].erase("finalists");
  CHECK(goal_from(all).search.finalists == 0);
  CHECK_THAT(broken("/material_file", "no_such_material.json"), Catch::Contains("no_such_material.json"));
  nlohmann::json unknown = test_goal_json();
  unknown["max_sagg_m"] = 0.1;
  CHECK_THAT(error_of(unknown), Catch::Contains("'max_sagg_m'"));
  nlohmann::json missing = test_goal_json();
  missing.erase("tool");
  CHECK_THAT(error_of(missing), Catch::Contains("'tool'"));
}

TEST_CASE("hang metrics: flat, turned over, bent over a cylinder, clearance over the tool", "[grasp_planning]") {
  const twin::SheetMesh mesh = twin::make_rectangular_sheet(1.0, 0.5, 0.02);
  cell::ToolSpec tool;
  tool.top_z_m = 0.6;
  twin::SheetPlacement level;
  level.origin_m = twin::Vec3(-0.5, -0.25, 1.0);
  const cell::HangMetrics flat = cell::measure_hang(mesh, twin::place_flat(mesh, level), 1.0, tool);
  CHECK(flat.sag_m == Approx(0.0).margin(1e-12));
  CHECK(flat.clearance_m == Approx(0.4));
  CHECK(flat.overturned_fraction == 0.0);
  CHECK(std::isinf(flat.min_bend_radius_m));

  twin::SheetPlacement upside_down = level;
  upside_down.rotation = twin::rotation_from_degrees(twin::Vec3(180, 0, 0));
  CHECK(cell::measure_hang(mesh, twin::place_flat(mesh, upside_down), 1.0, tool).overturned_fraction ==
        Approx(1.0));

  // Rolled around a cylinder of radius 0.1 m along u. A hinge sees the curvature across it, so
  // on offset rows (no edge along v; the steepest hinges are 30 degrees off) the estimate is
  // between R and R / cos(30 deg).
  const double radius = 0.1;
  twin::VecX x(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const double a = mesh.rest_uv[i].x() / radius;
    twin::vertex(x, i) = twin::Vec3(radius * std::sin(a), mesh.rest_uv[i].y(), 1.0 - radius + radius * std::cos(a));
  }
  const cell::HangMetrics rolled = cell::measure_hang(mesh, x, 1.0, tool);
  CHECK(rolled.min_bend_radius_m > 0.98 * radius);
  CHECK(rolled.min_bend_radius_m < 1.02 * radius / std::cos(M_PI / 6));
  CHECK(rolled.sag_m == Approx(2 * radius).epsilon(0.01));
  // 1 m of sheet is 1.59 turns; the normal n_z = cos(a) is below -0.5 for a in (2pi/3, 4pi/3) mod 2pi.
  CHECK(rolled.overturned_fraction > 0.2);

  // With a tool rectangle, only ply points above it count for clearance.
  tool.has_size = true;
  tool.size_m = twin::Vec2(0.1, 0.1);
  tool.centre_m = twin::Vec2(5.0, 5.0);
  CHECK(std::isinf(cell::measure_hang(mesh, x, 1.0, tool).clearance_m));
}

TEST_CASE("grippers go to the nearest arms and holds are checked for reachability", "[grasp_planning]") {
  const drivers::CellHardwareConfig cell = drivers::read_cell_hardware(kExamples + "/fake_cell.json");
  // Four holds near the fake cell's arm bases (LEFT -0.8,-0.65; RIGHT 0.8,-0.65; CENTER 0.7,0.75).
  const std::vector<twin::Vec2> uv = {{0.1, 0.1}, {1.0, 0.1}, {1.0, 0.9}, {0.1, 0.9}};
  const std::vector<twin::Vec3> holds = {{0.45, 0.38, 1.0}, {-0.45, 0.38, 1.0}, {-0.45, -0.38, 1.0}, {0.45, -0.38, 1.0}};
  const std::vector<twin::Grasp> g =
      cell::assign_grippers({"LEFT", "RIGHT", "CENTER", "MANUAL"}, uv, holds, 0.02, &cell);
  CHECK(g[0].hold_position_m.head<2>().isApprox(twin::Vec2(-0.45, -0.38)));  // LEFT
  CHECK(g[1].hold_position_m.head<2>().isApprox(twin::Vec2(0.45, -0.38)));   // RIGHT
  CHECK(g[2].hold_position_m.head<2>().isApprox(twin::Vec2(0.45, 0.38)));    // CENTER
  CHECK(g[3].hold_position_m.head<2>().isApprox(twin::Vec2(-0.45, 0.38)));   // MANUAL: what is left
  CHECK(g[0].clamp.material_point_m.isApprox(uv[2]));  // each keeps its own material point
  CHECK(cell::check_reachability(g, cell).empty());

  std::vector<twin::Grasp> too_high = g;
  too_high[1].hold_position_m.z() = 3.0;  // far beyond an iiwa7's 0.8 m reach from 0.5 m
  CHECK_THAT(cell::check_reachability(too_high, cell), Catch::StartsWith("arm RIGHT cannot reach"));
  std::vector<twin::Grasp> manual_far = g;
  manual_far[3].hold_position_m = twin::Vec3(5, 5, 3);  // the operator is not checked
  CHECK(cell::check_reachability(manual_far, cell).empty());
  CHECK_THROWS_WITH(cell::assign_grippers({"LEFT", "NOBODY"}, {uv[0], uv[1]}, {holds[0], holds[1]}, 0.02, &cell),
                    Catch::Contains("'NOBODY'"));
}

namespace {

// A small search: one ring, one slack, a few candidates.
nlohmann::json small_search_goal() {
  nlohmann::json j = test_goal_json();
  j["search"] = {{"inset_m", {0.10}}, {"ring_spacing_m", 0.25}, {"slack_factors", {0.04}},
                 {"random_candidates", 1}, {"screening_triangles", 250}, {"finalists", 2}, {"seed", 3}};
  return j;
}

}  // namespace

TEST_CASE("4 grippers on the composite ply: a feasible plan whose re-simulated sag is the predicted one",
          "[grasp_planning]") {
  const cell::GraspGoal goal = goal_from(small_search_goal());
  const cell::PlannerResult r = cell::plan_grasps(goal);
  INFO(r.plan.note);
  REQUIRE(r.plan.feasible);
  CHECK(r.screened == r.candidates);
  CHECK(r.candidates >= 4);
  CHECK(r.finalists == 2);
  REQUIRE(r.plan.grasps.size() == 4);
  CHECK(r.plan.predicted_sag_m <= goal.max_sag_m);
  CHECK(r.plan.predicted_sag_m > 0.0);
  for (const twin::Grasp& g : r.plan.grasps) CHECK(g.hold_position_m.z() == Approx(goal.hold_z_m));

  // Through the file and back, simulated again on the target mesh: the same hang.
  testing_support::TempDir dir("grasp_plan");
  const std::string path = (dir / "plan.json").string();
  twin::write_grasp_plan(r.plan, path);
  const twin::GraspPlan read = twin::read_grasp_plan(path);
  const twin::ShellModel model(goal.sheet.mesh, goal.material);
  const cell::HangEvaluation again = cell::evaluate_plan(model, read, goal);
  REQUIRE(again.solved);
  CHECK(again.feasible);
  CHECK(again.metrics.sag_m == Approx(read.predicted_sag_m).margin(1e-6));

  // Not worse than the hand-made four-grasp plan of the fake cell, scored the same way.
  const twin::GraspPlan hand = twin::read_grasp_plan(kExamples + "/four_grasp_plan.json");
  const cell::HangEvaluation hand_hang = cell::evaluate_plan(model, hand, goal);
  REQUIRE(hand_hang.solved);
  INFO("hand-made sag " << hand_hang.metrics.sag_m << " m, planned " << r.plan.predicted_sag_m << " m");
  CHECK(r.plan.predicted_sag_m <= hand_hang.metrics.sag_m);
}

TEST_CASE("by default every screened candidate is ranked on the target mesh", "[grasp_planning]") {
  nlohmann::json j = small_search_goal();
  j["search"].erase("finalists");
  const cell::GraspGoal goal = goal_from(j);
  const cell::PlannerResult r = cell::plan_grasps(goal);
  INFO(r.plan.note);
  int solved_on_screening = 0;
  for (const cell::CandidateResult& c : r.ranked) solved_on_screening += c.unreachable.empty() && c.screening.solved;
  REQUIRE(solved_on_screening >= 4);
  CHECK(r.finalists == solved_on_screening);
  CHECK(r.screening_rank_of_best >= 1);
  CHECK(r.screening_rank_of_best <= r.finalists);
  CHECK(r.largest_screening_sag_error_m > 0.0);  // the meshes differ (250 and 500 triangles)
  // The finalists lead the ranking in the target mesh's order: feasible first, then by sag.
  for (int i = 0; i < r.finalists; ++i) {
    const cell::CandidateResult& c = r.ranked[static_cast<std::size_t>(i)];
    REQUIRE(c.target.has_value());
    if (i == 0 || !c.target->solved) continue;
    const cell::HangEvaluation& before = *r.ranked[static_cast<std::size_t>(i - 1)].target;
    REQUIRE(before.solved);
    CHECK(before.feasible >= c.target->feasible);
    if (before.feasible == c.target->feasible) CHECK(before.metrics.sag_m <= c.target->metrics.sag_m);
  }
  REQUIRE(r.ranked.front().target->solved);
  CHECK(r.plan.predicted_sag_m == r.ranked.front().target->metrics.sag_m);
}

TEST_CASE("the plan file round-trips every field the planner writes", "[grasp_planning]") {
  twin::GraspPlan plan;
  twin::Grasp g;
  g.gripper = "LEFT";
  g.clamp = {"LEFT", twin::Vec2(0.123456789, 0.2), 0.02};
  g.hold_position_m = twin::Vec3(-0.41, 0.3333333333333, 1.0);
  plan.grasps = {g, g};
  plan.grasps[1].gripper = plan.grasps[1].clamp.id = "MANUAL";
  plan.predicted_sag_m = 0.1234567891234;
  plan.feasible = false;
  plan.note = "infeasible, best sag 0.210 m > limit 0.100 m";
  testing_support::TempDir dir("grasp_plan_rt");
  twin::write_grasp_plan(plan, (dir / "p.json").string());
  const twin::GraspPlan back = twin::read_grasp_plan((dir / "p.json").string());
  REQUIRE(back.grasps.size() == 2);
  CHECK(back.grasps[1].gripper == "MANUAL");
  CHECK(back.grasps[0].clamp.material_point_m == g.clamp.material_point_m);
  CHECK(back.grasps[0].hold_position_m == g.hold_position_m);
  CHECK(back.predicted_sag_m == plan.predicted_sag_m);
  CHECK_FALSE(back.feasible);
  CHECK(back.note == plan.note);
}

TEST_CASE("2 grippers with a tight sag limit: infeasible, with the reason", "[grasp_planning]") {
  nlohmann::json j = small_search_goal();
  j["max_sag_m"] = 0.10;
  const cell::GraspGoal goal = goal_from(j);
  cell::PlannerOptions options;
  options.grippers = 2;
  const cell::PlannerResult r = cell::plan_grasps(goal, options);
  INFO(r.plan.note);
  CHECK_FALSE(r.plan.feasible);
  REQUIRE(r.plan.grasps.size() == 2);
  CHECK(r.plan.grasps[0].gripper == "LEFT");
  CHECK(r.plan.grasps[1].gripper == "RIGHT");
  CHECK(r.plan.predicted_sag_m > 0.10);
  CHECK_THAT(r.plan.note, Catch::StartsWith("infeasible, best sag") && Catch::Contains("> limit 0.100 m"));
}

TEST_CASE("local refinement on the target mesh never makes the plan worse and is re-simulated exactly",
          "[grasp_planning]") {
  nlohmann::json j = small_search_goal();
  j["search"]["finalists"] = 1;
  const cell::PlannerResult plain = cell::plan_grasps(goal_from(j));
  j["search"]["refine_evaluations"] = 8;
  const cell::GraspGoal goal = goal_from(j);
  const cell::PlannerResult refined = cell::plan_grasps(goal);
  INFO(refined.plan.note);
  REQUIRE(plain.plan.feasible);
  REQUIRE(refined.plan.feasible);
  CHECK(refined.refine_evaluations >= 1);
  CHECK(refined.refine_evaluations <= 8);
  CHECK(refined.plan.predicted_sag_m <= plain.plan.predicted_sag_m);
  CHECK(refined.refined == (refined.plan.predicted_sag_m < plain.plan.predicted_sag_m));
  const twin::ShellModel model(goal.sheet.mesh, goal.material);
  const cell::HangEvaluation again = cell::evaluate_plan(model, refined.plan, goal);
  REQUIRE(again.solved);
  CHECK(again.metrics.sag_m == Approx(refined.plan.predicted_sag_m).margin(1e-6));
  for (const twin::Grasp& g : refined.plan.grasps) {
    CHECK(g.clamp.material_point_m.x() >= 0.0);
    CHECK(g.clamp.material_point_m.x() <= 1.17);
    CHECK(g.clamp.material_point_m.y() >= 0.0);
    CHECK(g.clamp.material_point_m.y() <= 0.975);
  }
}

TEST_CASE("a hang evaluation sent to another rank arrives bit for bit", "[grasp_planning]") {
  const cell::GraspGoal goal = goal_from(small_search_goal());
  const twin::ShellModel model(goal.sheet.mesh, goal.material);
  const cell::HangEvaluation e = cell::evaluate_plan(model, twin::read_grasp_plan(kExamples + "/four_grasp_plan.json"), goal);
  REQUIRE(e.solved);
  const std::string bytes = cell::encode_hang_evaluation(e);
  const cell::HangEvaluation back = cell::decode_hang_evaluation(bytes);
  CHECK(back.solved == e.solved);
  CHECK(back.feasible == e.feasible);
  CHECK(back.reason == e.reason);
  CHECK(back.metrics.sag_m == e.metrics.sag_m);
  CHECK(back.metrics.lowest_z_m == e.metrics.lowest_z_m);
  CHECK(back.metrics.clearance_m == e.metrics.clearance_m);
  CHECK(back.metrics.min_bend_radius_m == e.metrics.min_bend_radius_m);
  CHECK(back.metrics.overturned_fraction == e.metrics.overturned_fraction);
  CHECK(back.seconds == e.seconds);
  CHECK(back.x == e.x);
  CHECK_THROWS(cell::decode_hang_evaluation(bytes.substr(0, bytes.size() - 1)));
  CHECK_THROWS(cell::decode_hang_evaluation(bytes + "x"));
}

TEST_CASE("plan_grasps writes a plan, scores a hand-made one and exits 0, 2 or 1", "[grasp_planning]") {
  testing_support::TempDir dir("plan_grasps_tool");
  nlohmann::json j = small_search_goal();
  j["material_file"] = kExamples + "/composite_identified.json";
  const std::string goal = (dir / "goal.json").string(), plan = (dir / "plan.json").string();
  std::ofstream(goal) << j.dump(2);
  const std::string tool = PLAN_GRASPS_EXE;
  auto run = [](const std::string& command) {
    const int status = std::system((command + " > /dev/null 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  CHECK(run(tool + " --goal " + goal + " --out " + plan + " --cell " + kExamples + "/fake_cell.json") == 0);
  const twin::GraspPlan written = twin::read_grasp_plan(plan);
  CHECK(written.feasible);
  CHECK(written.grasps.size() == 4);
  CHECK(std::isfinite(written.predicted_sag_m));
  CHECK(run(tool + " --goal " + goal + " --score " + plan) == 0);
  CHECK(run(tool + " --goal " + goal + " --score " + kExamples + "/four_grasp_plan.json") == 0);
  j["max_sag_m"] = 0.05;
  std::ofstream(goal) << j.dump(2);
  CHECK(run(tool + " --goal " + goal + " --score " + kExamples + "/four_grasp_plan.json") == 2);
  j["max_sag_m"] = "deep";
  std::ofstream(goal) << j.dump(2);
  CHECK(run(tool + " --goal " + goal + " --out " + plan) == 1);
}
