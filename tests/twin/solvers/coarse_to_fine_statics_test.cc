#include <catch2/catch.hpp>

#include <cmath>

#include "twin/solvers/coarse_to_fine_statics.h"
#include "tests/support/vertex_distance.h"

namespace twin::coarse_to_fine_statics_test {
namespace {

constexpr double kWidth_m = 0.6, kHeight_m = 0.4;

SheetMesh sheet_of(int triangles) {
  return make_rectangular_sheet(kWidth_m, kHeight_m, edge_length_for_triangle_count(kWidth_m, kHeight_m, triangles));
}

// A sheet held at four points near its corners, `pull` of the way from flat outward (negative:
// inward, so that it sags), 1 m up.
struct HeldSheet {
  explicit HeldSheet(int triangles, double pull = 0.0)
      : model(sheet_of(triangles), Material{}),
        clamps(model.mesh(), {{"A", Vec2(0.03, 0.03), 0.02},
                              {"B", Vec2(kWidth_m - 0.03, 0.03), 0.02},
                              {"C", Vec2(kWidth_m - 0.03, kHeight_m - 0.03), 0.02},
                              {"D", Vec2(0.03, kHeight_m - 0.03), 0.02}}) {
    placement.origin_m = Vec3(0, 0, 1);
    flat = place_flat(model.mesh(), placement);
    const Vec3 centre = placement.to_world(Vec2(kWidth_m / 2, kHeight_m / 2));
    poses.resize(4);
    for (int i = 0; i < 4; ++i) {
      const Vec3 p = placement.to_world(clamps[i].spec().material_point_m);
      poses[i].position_m = centre + (1.0 + pull) * (p - centre);
    }
  }
  ShellModel model;
  ClampSet clamps;
  SheetPlacement placement;
  std::vector<ClampPose> poses;
  VecX flat;
};

using testing_support::largest_vertex_distance;

TEST_CASE("interpolated positions follow an affine deformation exactly", "[twin][solver]") {
  const SheetMesh coarse = sheet_of(60), fine = sheet_of(500);
  Mat3 a;
  a << 0.9, 0.2, 0.0, -0.1, 1.1, 0.0, 0.3, -0.2, 1.0;
  const Vec3 b(0.1, -0.2, 1.0);
  auto deformed = [&](const SheetMesh& mesh) {
    VecX x(3 * mesh.vertex_count());
    for (int v = 0; v < mesh.vertex_count(); ++v) x.segment<3>(3 * v) = a * Vec3(mesh.rest_uv[v].x(), mesh.rest_uv[v].y(), 0) + b;
    return x;
  };
  const VecX carried = interpolate_positions(MaterialPointMap(coarse, fine.rest_uv), deformed(coarse));
  CHECK(largest_vertex_distance(carried, deformed(fine)) < 1e-12);
}

// Issue 37, item 3: a different start, the same answer. Where the direct solve from flat and the
// solve through coarser meshes reach the same equilibrium, they agree within 0.1 mm per vertex
// and 1e-8 in relative energy (both converge to the static solver's residual tolerance).
TEST_CASE("through coarser meshes the static solve reaches the direct solve's equilibrium", "[twin][solver]") {
  // Pulled 1 % outward, the sheet is in tension: one equilibrium, which both must find.
  const double pull = GENERATE(0.01, 0.0);
  HeldSheet sheet(1200, pull);
  VecX direct = sheet.flat;
  StaticSolver statics(sheet.model);
  const SolveReport d = statics.solve(sheet.clamps, sheet.poses, direct);
  REQUIRE(d.usable());

  CoarseToFineStatics multilevel(sheet.model, sheet.clamps, {sheet_of(75), sheet_of(300)});
  CHECK(multilevel.level_count() == 2);
  VecX x = sheet.flat;
  const CoarseToFineReport r = multilevel.solve(sheet.poses, x);
  INFO("pull " << pull << ": direct " << d.brief() << "; through coarser meshes " << r.total.brief());
  REQUIRE(r.total.usable());
  CHECK_FALSE(r.fell_back);
  REQUIRE(r.levels.size() == 3);
  CHECK(r.level_triangles.back() == sheet.model.mesh().triangle_count());
  CHECK(r.level_triangles.front() < r.level_triangles[1]);
  CHECK(largest_vertex_distance(x, direct) < 1e-4);
  CHECK(std::abs(r.total.energy_J - d.energy_J) <= 1e-8 * std::abs(d.energy_J));
  // The fine mesh corrects a start that is already near: fewer Newton iterations than from flat.
  CHECK(r.levels.back().iterations < d.iterations);
}

TEST_CASE("a failed solve through coarser meshes leaves the start as it was", "[twin][solver]") {
  HeldSheet sheet(300, -0.05);
  CoarseToFineStatics multilevel(sheet.model, sheet.clamps, {sheet_of(75)});
  NewtonOptions starved = default_static_options();
  // No level can converge, nor the fallback: nothing meets a zero tolerance.
  starved.max_iterations = 1;
  starved.residual_tolerance = 0.0;
  starved.round_off_residual = 0.0;
  VecX x = sheet.flat;
  const CoarseToFineReport r = multilevel.solve(sheet.poses, x, starved);
  CHECK_FALSE(r.total.usable());
  CHECK(r.fell_back);
  CHECK(r.total.fallbacks == 1);
  CHECK(x == sheet.flat);
}

TEST_CASE("coarse meshes that do not cover the sheet, or are not coarser, are refused or skipped", "[twin][solver]") {
  HeldSheet sheet(300);
  // Half the sheet: the clamps on the other half have no material point there.
  const SheetMesh half = make_rectangular_sheet(kWidth_m / 2, kHeight_m, 0.05);
  try {
    CoarseToFineStatics multilevel(sheet.model, sheet.clamps, {half});
    FAIL("a coarse mesh that does not cover the sheet was taken");
  } catch (const std::invalid_argument& e) {
    CHECK_THAT(e.what(), Catch::Contains("coarse mesh of " + std::to_string(half.triangle_count()) + " triangles"));
  }
  // As fine as the sheet itself: no gain, not used.
  CoarseToFineStatics same(sheet.model, sheet.clamps, {sheet_of(300)});
  CHECK(same.level_count() == 0);
  VecX x = sheet.flat;
  const CoarseToFineReport r = same.solve(sheet.poses, x);
  CHECK(r.total.usable());
  CHECK(r.levels.size() == 1);
}

}  // namespace
}  // namespace twin::coarse_to_fine_statics_test
