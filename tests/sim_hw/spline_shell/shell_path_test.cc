// The lab's protocol on the shell, stage by stage: a stage that opens a jaw is recognised as a
// fall, and replaying one stage from the equilibrium before it reaches what the whole path
// reached there (so a refinement study can let each level fall on its own physics).

#include <catch2/catch.hpp>

#include "sim_hw/spline_shell/shell_path.h"
#include "tests/sim_hw/spline_shell/shell_fixtures.h"

namespace ss = sim_hw::spline_shell;

namespace {

constexpr double W = 0.3, H = 0.25;

// Two jaws near the top corners of a 30 x 25 cm sheet.
std::vector<ss::SquareJaw> two_jaws() {
  return {ss::square_jaw("A", ss::Vec2(0.05, 0.21), 0.015, W, H), ss::square_jaw("B", ss::Vec2(0.25, 0.21), 0.015, W, H)};
}

twin::ClampPose pose(double x, double z, bool engaged) {
  twin::ClampPose p;
  p.position_m = ss::Vec3(x, 0.0, z);
  p.engaged = engaged;
  return p;
}

// Gripped level and let go, B moved 4 cm in (a sag), B opened (its side falls).
std::vector<sim_hw::real_sheet::PathStage> lift_sag_release() {
  std::vector<sim_hw::real_sheet::PathStage> stages(3);
  stages[0].poses = {pose(0.05, 0.5, true), pose(0.25, 0.5, true)};
  stages[1].poses = {pose(0.05, 0.5, true), pose(0.21, 0.5, true)};
  stages[2].poses = {pose(0.05, 0.5, true), pose(0.21, 0.5, false)};
  return stages;
}

}  // namespace

TEST_CASE("spline shell: a replayed stage reaches what the path reached", "[spline_shell][path]") {
  const std::vector<ss::SquareJaw> jaws = two_jaws();
  ss::ShellModel model(ss::SplinePatch(ss::jaw_knots(3, W, 0, jaws, 0.06, 0.015), ss::jaw_knots(3, H, 1, jaws, 0.06, 0.015)),
                       shell_fixtures::composite());
  const std::vector<sim_hw::real_sheet::PathStage> stages = lift_sag_release();
  const ss::ShellPathResult path = ss::follow_path(model, jaws, stages);
  INFO(path.failure);
  REQUIRE(path.usable());
  REQUIRE(path.stages.size() == 3);
  CHECK_FALSE(ss::lets_go(path.holds[0], stages[1], jaws));
  CHECK(ss::lets_go(path.holds[1], stages[2], jaws));
  CHECK(path.holds[2].jaws.size() == 1);

  ss::ShellHolds after;
  ss::ShellSolveReport report;
  const ss::VecX replayed = ss::replay_stage(model, jaws, path.stages[1], path.holds[1], stages[2], &after, {}, &report);
  CHECK(report.converged);
  CHECK(report.iterations > 0);
  CHECK((replayed - path.stages[2]).lpNorm<Eigen::Infinity>() < 1e-12);
  REQUIRE(after.jaws.size() == 1);
  CHECK(after.jaws[0].jaw.id == "A");
  // It fell: the side B held is now well below where B let it go.
  const ss::Vec3 b_before = model.patch().position(path.stages[1], jaws[1].material_point_m);
  const ss::Vec3 b_after = model.patch().position(replayed, jaws[1].material_point_m);
  CHECK(b_after.z() < b_before.z() - 0.05);
}

TEST_CASE("spline shell: a carried path keeps its falls on the coarse branch unless told to replay them",
          "[spline_shell][path]") {
  const std::vector<ss::SquareJaw> jaws = two_jaws();
  const ss::KnotVector ku = ss::jaw_knots(3, W, 0, jaws, 0.06, 0.015), kv = ss::jaw_knots(3, H, 1, jaws, 0.06, 0.015);
  ss::ShellModel coarse(ss::SplinePatch(ku, kv), shell_fixtures::composite());
  ss::ShellModel fine(ss::SplinePatch(ss::refined(ku), ss::refined(kv)), shell_fixtures::composite());
  const std::vector<sim_hw::real_sheet::PathStage> stages = lift_sag_release();
  const ss::ShellPathResult path = ss::follow_path(coarse, jaws, stages);
  REQUIRE(path.usable());
  const ss::Vec2 corner(0.28, 0.02);  // the released side's far corner: where a fall ends shows most
  const ss::Vec3 coarse_corner = coarse.patch().position(path.stages[2], corner);

  const ss::CarriedPath carried = ss::carry_path(coarse, path.stages, path.holds, fine, jaws, stages);
  CHECK(carried.replayed.empty());
  REQUIRE(carried.stages.size() == 3);
  REQUIRE(carried.holds[2].jaws.size() == 1);
  // Carried: the fine level re-settles the coarse fallen shape, a refinement's change away.
  CHECK((fine.patch().position(carried.stages[2], corner) - coarse_corner).norm() < 0.01);

  ss::ShellPathOptions replay;
  replay.replay_falls = true;
  const ss::CarriedPath replayed = ss::carry_path(coarse, path.stages, path.holds, fine, jaws, stages, replay);
  REQUIRE(replayed.replayed == std::vector<int>{2});
  REQUIRE(replayed.holds[2].jaws.size() == 1);
  CHECK(replayed.holds[2].jaws[0].jaw.id == "A");
  // The fall again on the fine level, from its own stage 2: it lands below where B let go.
  CHECK(fine.patch().position(replayed.stages[2], jaws[1].material_point_m).z() < 0.45);
}
