// A composite sheet held level by two square jaws and let go into gravity, solved on three nested
// spline spaces (each level's equilibrium carried exactly onto the next by knot insertion and
// solved again there): the pads move rigidly with their jaws, the jaws carry the sheet's weight,
// and the markers converge, the change between the two finest levels well below the change
// before it (observed order printed).

#include <cmath>
#include <cstdio>
#include <memory>

#include <catch2/catch.hpp>

#include "sim_hw/spline_shell/shell_equilibrium.h"
#include "tests/sim_hw/spline_shell/shell_fixtures.h"

namespace ss = sim_hw::spline_shell;

TEST_CASE("spline shell: square jaws hold their pads rigidly and nothing else", "[spline_shell]") {
  const double W = 0.3, H = 0.25;
  const std::vector<ss::SquareJaw> jaws = {ss::square_jaw("A", ss::Vec2(0.06, 0.22), 0.015, W, H)};
  const ss::SplinePatch patch(ss::jaw_knots(3, W, 0, jaws, 0.03, 0.005), ss::jaw_knots(3, H, 1, jaws, 0.03, 0.005));
  const ss::ShellModel model(patch, shell_fixtures::composite());
  ss::VecX x = patch.flat_positions();
  ss::ShellHolds holds;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, ss::Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const ss::Vec3 c(0.1, 0.2, 0.3);
  holds.jaws.push_back({jaws[0], c, R});
  const std::vector<int> held = ss::apply_holds(model, holds, x);
  const double a = jaws[0].half_side_m;
  CHECK(a == Approx(0.015 * std::sqrt(M_PI) / 2));
  // On the pad the surface is the rigid motion, with its normal R's third column.
  for (double s : {-1.0, -0.5, 0.0, 0.7, 1.0}) {
    for (double t : {-1.0, -0.3, 0.4, 1.0}) {
      const ss::Vec2 uv = jaws[0].material_point_m + a * ss::Vec2(s, t);
      CHECK((patch.position(x, uv) - (c + R * ss::Vec3(a * s, a * t, 0))).norm() < 1e-12);
      CHECK((patch.normal(x, uv) - R.col(2)).norm() < 1e-10);
    }
  }
  // Off the pad the flat sheet's controls are untouched: the hold reaches no further than the
  // basis functions that meet the pad.
  const ss::VecX flat = patch.flat_positions();
  int moved = 0;
  for (int k = 0; k < patch.control_count(); ++k) moved += (x.segment<3>(3 * k) - flat.segment<3>(3 * k)).norm() > 0;
  CHECK(moved == static_cast<int>(held.size()));
  // Distances from the pad: none inside, to its side along an axis, to its corner diagonally.
  CHECK(ss::distance_to_pad_m(jaws[0], jaws[0].material_point_m + ss::Vec2(0.5 * a, -0.9 * a)) == 0.0);
  CHECK(ss::distance_to_pad_m(jaws[0], jaws[0].material_point_m + ss::Vec2(a + 0.01, 0.2 * a)) == Approx(0.01));
  CHECK(ss::distance_to_pad_m(jaws[0], jaws[0].material_point_m - ss::Vec2(a + 0.03, a + 0.04)) == Approx(0.05));
}

TEST_CASE("spline shell: a sheet held by two jaws converges under refinement and hangs from them", "[spline_shell]") {
  const double W = 0.3, H = 0.25;
  std::vector<ss::Vec2> markers;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 5; ++i) markers.push_back(ss::Vec2(0.03 + 0.06 * i, 0.02 + 0.06 * j));
  }
  const std::vector<ss::SquareJaw> jaws = {ss::square_jaw("A", ss::Vec2(0.06, 0.22), 0.015, W, H),
                                           ss::square_jaw("B", ss::Vec2(0.24, 0.22), 0.015, W, H)};
  ss::KnotVector ku = ss::jaw_knots(3, W, 0, jaws, 0.04, 0.01), kv = ss::jaw_knots(3, H, 1, jaws, 0.04, 0.01);
  std::vector<std::vector<ss::Vec3>> seen;
  ss::VecX previous;
  std::unique_ptr<ss::ShellModel> coarser;
  for (int level = 0; level < 3; ++level) {
    if (level > 0) ku = ss::refined(ku), kv = ss::refined(kv);
    auto model = std::make_unique<ss::ShellModel>(ss::SplinePatch(ku, kv), shell_fixtures::composite(), markers);
    ss::ShellHolds holds;
    for (const ss::SquareJaw& j : jaws) {
      holds.jaws.push_back({j, ss::Vec3(j.material_point_m.x(), j.material_point_m.y(), 0.0), Eigen::Matrix3d::Identity()});
    }
    ss::VecX x = level == 0 ? model->patch().flat_positions() : ss::refine_controls(coarser->patch(), previous, model->patch());
    ss::ShellSolveOptions options;
    options.initial_damping_1_s2 = level == 0 ? 100.0 : 0.0;  // the first level falls, overdamped
    const ss::ShellSolveReport report = ss::solve_shell(*model, holds, x, options);
    INFO("level " << level << ": " << report.message);
    REQUIRE(report.converged);
    std::printf("held sheet level %d: %d controls, %d Newton iterations\n", level, model->patch().control_count(),
                report.iterations);
    // The jaws carry the weight.
    const ss::Vec3 lift = ss::holding_force_N(*model, holds, x);
    CHECK(lift.z() == Approx(model->total_weight_N()).epsilon(1e-6));
    CHECK(std::abs(lift.x()) < 1e-6 * model->total_weight_N());
    seen.push_back(model->marker_positions(x));
    previous = x;
    coarser = std::move(model);
  }
  double change[2] = {0, 0}, worst[2] = {0, 0};
  for (int d = 0; d < 2; ++d) {
    for (std::size_t m = 0; m < markers.size(); ++m) {
      const double e = (seen[d][m] - seen[d + 1][m]).norm();
      change[d] += e / markers.size();
      worst[d] = std::max(worst[d], e);
    }
  }
  double lowest = 0;
  for (const ss::Vec3& p : seen.back()) lowest = std::min(lowest, p.z());
  std::printf("held sheet: markers move %.4f mm mean (max %.4f) from level 0 to 1, %.4f mm (max %.4f) from 1 to 2: "
              "observed order %.2f; lowest marker %.1f mm below the jaws\n",
              1e3 * change[0], 1e3 * worst[0], 1e3 * change[1], 1e3 * worst[1], std::log2(change[0] / change[1]), -1e3 * lowest);
  CHECK(lowest < -0.1);  // it hangs: the flat sheet is not the answer
  CHECK(change[1] < 0.25 * change[0]);
  CHECK(change[1] < 3e-4);
}
