#include "twin/solvers/quasi_static.h"

#include <catch2/catch.hpp>

namespace twin::quasi_static_test {
namespace {

struct Rig {
  Material material;
  std::unique_ptr<ShellModel> model;
  ClampSet clamps;
  SheetPlacement placement;
  std::vector<ClampPose> poses;

  Rig() {
    material.bending_rigidity_u_Nm = material.bending_rigidity_v_Nm = 2e-3;
    model = std::make_unique<ShellModel>(make_rectangular_sheet(0.4, 0.3, 0.04), material);
    const std::vector<ClampSpec> specs = {{"A", Vec2(0.03, 0.03), 0.02},
                                          {"B", Vec2(0.37, 0.04), 0.02},
                                          {"C", Vec2(0.35, 0.27), 0.02},
                                          {"D", Vec2(0.04, 0.26), 0.02}};
    clamps = ClampSet(model->mesh(), specs);
    placement.origin_m = Vec3(0, 0, 1);
    const Vec3 centre = placement.to_world(Vec2(0.2, 0.15));
    for (const ClampSpec& s : specs) {
      ClampPose p;
      p.position_m = centre + 0.92 * (placement.to_world(s.material_point_m) - centre);
      poses.push_back(p);
    }
  }
};

double lowest_z(const VecX& x) {
  double z = 1e300;
  for (int i = 0; i < x.size() / 3; ++i) z = std::min(z, x(3 * i + 2));
  return z;
}

TEST_CASE("continuation follows the clamps through stages", "[twin][quasi_static]") {
  Rig rig;
  QuasiStaticSolver solver(*rig.model, rig.clamps);
  VecX x = place_flat(rig.model->mesh(), rig.placement);
  std::vector<ClampPose> released(rig.poses.size());
  for (auto& p : released) p.engaged = false;
  const ContinuationReport hold = solver.move(released, rig.poses, x);
  INFO(hold.brief());
  REQUIRE(hold.usable());
  const double held_low = lowest_z(x);
  CHECK(held_low < 1.0);

  // Raise clamp A by 10 cm: several increments, the sheet's low point moves.
  std::vector<ClampPose> raised = rig.poses;
  raised[0].position_m.z() += 0.10;
  ContinuationOptions options;
  options.increment_m = 0.02;
  const ContinuationReport lift = solver.move(rig.poses, raised, x, options);
  INFO(lift.brief());
  REQUIRE(lift.usable());
  CHECK(lift.increments >= 5);
  // Every clamped vertex sits where its clamp holds it.
  VecX held = x;
  rig.clamps.hold(raised, held);
  CHECK((held - x).norm() < 1e-12);

  // Releasing clamp C lets the sheet hang lower.
  std::vector<ClampPose> one_off = raised;
  one_off[2].engaged = false;
  const ContinuationReport release = solver.move(raised, one_off, x, options);
  INFO(release.brief());
  REQUIRE(release.usable());
  CHECK(lowest_z(x) < held_low - 0.01);
}

TEST_CASE("a failed move leaves the sheet where it was", "[twin][quasi_static]") {
  Rig rig;
  QuasiStaticSolver solver(*rig.model, rig.clamps);
  VecX x = place_flat(rig.model->mesh(), rig.placement);
  std::vector<ClampPose> released(rig.poses.size());
  for (auto& p : released) p.engaged = false;
  ContinuationOptions starved;
  starved.newton.max_iterations = 1;
  const VecX before = x;
  const ContinuationReport report = solver.move(released, rig.poses, x, starved);
  CHECK_FALSE(report.usable());
  CHECK(x == before);
}

TEST_CASE("a clamp that grips again takes the sheet as it is", "[twin][quasi_static]") {
  Rig rig;
  QuasiStaticSolver solver(*rig.model, rig.clamps);
  VecX x = place_flat(rig.model->mesh(), rig.placement);
  std::vector<ClampPose> released(rig.poses.size());
  for (auto& p : released) p.engaged = false;
  REQUIRE(solver.move(released, rig.poses, x).usable());
  std::vector<ClampPose> without_c = rig.poses;
  without_c[2].engaged = false;
  REQUIRE(solver.move(rig.poses, without_c, x).usable());
  // Re-grip C exactly where and how its material is now: nothing should jump.
  std::vector<ClampPose> regrip = without_c;
  regrip[2].engaged = true;
  regrip[2].position_m = rig.clamps[2].material_point_position(x);
  regrip[2].rotation = rig.clamps[2].material_frame(x);
  const VecX before = x;
  const ContinuationReport report = solver.move(without_c, regrip, x);
  INFO(report.brief());
  REQUIRE(report.usable());
  CHECK((x - before).cwiseAbs().maxCoeff() < 5e-3);  // m; the patch is only made rigid
  CHECK(rig.clamps[2].material_frame(x).isUnitary(1e-9));
}

}  // namespace
}  // namespace twin::quasi_static_test
