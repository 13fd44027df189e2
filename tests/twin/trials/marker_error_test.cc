#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "twin/trials/marker_error.h"
#include "twin/mesh/material_point.h"
#include "twin/trials/trial_simulation.h"

namespace twin::marker_error_test {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST_CASE("Algorithm 1 scores each observed point by its nearest predicted vertex", "[twin][metrics]") {
  VecX x(9);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  const std::vector<Vec3> observed = {Vec3(0.1, 0, 0), Vec3(1, 0, 0.3), Vec3(kNaN, kNaN, kNaN), Vec3(0, 0.6, 0)};
  const StageError e = nearest_vertex_error(observed, x);
  CHECK(e.points_used == 3);
  CHECK(e.per_point_m[0] == Approx(0.1));
  CHECK(e.per_point_m[1] == Approx(0.3));
  CHECK(std::isnan(e.per_point_m[2]));
  CHECK(e.per_point_m[3] == Approx(0.4));  // (0, 1, 0) is nearer than (0, 0, 0)
  CHECK(e.mean_m == Approx(0.8 / 3));
  CHECK(e.max_m == Approx(0.4));
  CHECK(e.score(0.5) == Approx(0.8 / 3 + 0.2));
  CHECK(e.score(2.0) == Approx(0.8 / 3 + 0.8));
}

TEST_CASE("correspondence error pairs each marker with its own prediction", "[twin][metrics]") {
  const std::vector<Vec3> predicted = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  // Swapped markers: Algorithm 1 would see no error, the correspondence error sees 1 m each.
  const std::vector<Vec3> observed = {Vec3(1, 0, 0), Vec3(0, 0, 0)};
  const StageError e = correspondence_error(observed, predicted);
  CHECK(e.mean_m == Approx(1.0));
  VecX x(6);
  x << 0, 0, 0, 1, 0, 0;
  CHECK(nearest_vertex_error(observed, x).max_m == Approx(0.0));
  CHECK_THROWS_WITH(correspondence_error({Vec3::Zero()}, predicted),
                    Catch::Contains("1 observed markers but 2 predicted"));
}

TEST_CASE("material points move with their host triangle", "[twin][metrics]") {
  const SheetMesh mesh = make_rectangular_sheet(0.4, 0.3, 0.05);
  const MaterialPointMap map(mesh, {Vec2(0.0, 0.0), Vec2(0.4, 0.3), Vec2(0.123, 0.211)});
  // Any affine map of the plane carries the points exactly, barycentric weights being affine.
  Mat3 a;
  a << 1.1, 0.2, 0.0, -0.1, 0.9, 0.0, 0.3, 0.4, 1.0;
  const Vec3 t(0.5, -0.2, 1.0);
  VecX x(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) x.segment<3>(3 * v) = a * Vec3(mesh.rest_uv[v].x(), mesh.rest_uv[v].y(), 0) + t;
  const std::vector<Vec3> p = map.positions(x);
  CHECK((p[2] - (a * Vec3(0.123, 0.211, 0) + t)).norm() < 1e-12);
  CHECK((p[1] - (a * Vec3(0.4, 0.3, 0) + t)).norm() < 1e-12);
  // The gradient map is the transpose of the position map.
  const std::vector<Vec3> dp = {Vec3(1, 2, 3), Vec3(-1, 0, 1), Vec3(0.5, 0.5, -2)};
  VecX dx = VecX::Zero(x.size());
  map.add_gradient(dp, dx);
  const VecX y = VecX::Random(x.size());
  double lhs = 0.0;
  const std::vector<Vec3> py = map.positions(y);
  for (int i = 0; i < 3; ++i) lhs += dp[i].dot(py[i]);
  CHECK(lhs == Approx(dx.dot(y)).epsilon(1e-12));
  CHECK_THROWS_WITH(MaterialPointMap(mesh, {Vec2(0.1, 0.1), Vec2(0.5, 0.1)}),
                    Catch::Contains("material point 1 at (0.5, 0.1) m is not on the sheet"));
}

TEST_CASE("the level placement fits the clamps' first positions", "[twin][metrics]") {
  const std::vector<ClampSpec> clamps = {{"A", Vec2(0.1, 0.1), 0.0}, {"B", Vec2(0.9, 0.1), 0.0}, {"C", Vec2(0.5, 0.7), 0.0}};
  SheetPlacement truth;
  truth.rotation = Eigen::AngleAxisd(0.4, Vec3::UnitZ()).toRotationMatrix();
  truth.origin_m = Vec3(0.2, -0.3, 1.1);
  std::vector<ClampPose> poses(3);
  for (int i = 0; i < 3; ++i) poses[i].position_m = truth.to_world(clamps[i].material_point_m);
  const SheetPlacement fit = fit_level_placement(clamps, poses);
  CHECK((fit.rotation - truth.rotation).norm() < 1e-12);
  CHECK((fit.origin_m - truth.origin_m).norm() < 1e-12);
  for (ClampPose& p : poses) p.engaged = false;
  CHECK_THROWS_WITH(fit_level_placement(clamps, poses), Catch::Contains("no clamp holds the sheet"));
}

}  // namespace
}  // namespace twin::marker_error_test
