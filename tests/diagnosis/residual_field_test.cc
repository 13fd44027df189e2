#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "twin/model/clamp.h"
#include "twin/diagnosis/residual_field.h"
#include "twin/mesh/sheet_mesh.h"

using twin::Vec2;
using twin::Vec3;
using twin::VecX;

namespace {

// The rest mesh bent into a cylinder of radius R about an axis along u: curvature 1/R along v.
VecX cylinder(const twin::SheetMesh& mesh, double radius_m) {
  VecX x(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const Vec2& uv = mesh.rest_uv[i];
    const double a = uv.y() / radius_m;
    x.segment<3>(3 * i) = Vec3(uv.x(), radius_m * std::sin(a), radius_m * (1.0 - std::cos(a)));
  }
  return x;
}

bool interior(const twin::SheetMesh& mesh, int i, double margin) {
  const Vec2& uv = mesh.rest_uv[i];
  return uv.x() > margin && uv.y() > margin && uv.x() < 1.0 - margin && uv.y() < 0.8 - margin;
}

twin::TrialStage stage(std::optional<double> time_s, double lift_m, bool second_engaged = true) {
  twin::TrialStage s;
  s.time_s = time_s;
  twin::ClampPose a, b;
  a.position_m = Vec3(0.0, 0.0, 1.0 + lift_m);
  b.position_m = Vec3(1.0, 0.0, 1.0);
  b.engaged = second_engaged;
  s.poses = {a, b};
  return s;
}

}  // namespace

TEST_CASE("vertex curvature of a cylinder is its 1/R, in either direction, and 0 when flat", "[diagnosis]") {
  const twin::SheetMesh mesh = twin::make_rectangular_sheet(1.0, 0.8, 0.05);
  for (double radius : {0.5, 2.0}) {
    const std::vector<double> k = twin::diagnosis::vertex_curvatures_1_m(mesh, cylinder(mesh, radius));
    int checked = 0;
    for (int i = 0; i < mesh.vertex_count(); ++i) {
      if (!interior(mesh, i, 0.06)) continue;
      INFO("vertex " << i << " radius " << radius);
      CHECK(k[i] == Approx(1.0 / radius).epsilon(0.07));
      ++checked;
    }
    CHECK(checked > 100);
  }
  // The mesh turned by 90 degrees (its rows along v): the estimate does not depend on the pattern.
  twin::SheetMesh turned = mesh;
  for (Vec2& uv : turned.rest_uv) uv = Vec2(uv.y(), uv.x());
  for (auto& t : turned.triangles) std::swap(t[1], t[2]);  // keep counter-clockwise
  const std::vector<double> k = twin::diagnosis::vertex_curvatures_1_m(turned, cylinder(turned, 1.0));
  for (int i = 0; i < turned.vertex_count(); ++i) {
    const Vec2& uv = turned.rest_uv[i];
    if (uv.x() > 0.06 && uv.y() > 0.06 && uv.x() < 0.74 && uv.y() < 0.94) CHECK(k[i] == Approx(1.0).epsilon(0.07));
  }
  VecX flat(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) flat.segment<3>(3 * i) = Vec3(mesh.rest_uv[i].x(), mesh.rest_uv[i].y(), 0.3);
  for (double v : twin::diagnosis::vertex_curvatures_1_m(mesh, flat)) CHECK(v == Approx(0.0).margin(1e-9));
}

TEST_CASE("vertex normals of a cylinder point away from its axis", "[diagnosis]") {
  const twin::SheetMesh mesh = twin::make_rectangular_sheet(1.0, 0.8, 0.05);
  const double radius = 0.5;
  const VecX x = cylinder(mesh, radius);
  const std::vector<Vec3> n = twin::diagnosis::vertex_normals(mesh, x);
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    if (!interior(mesh, i, 0.06)) continue;
    // The axis is the line y = 0, z = R; the flat sheet's normal is +z, so the normal points to it.
    const Vec3 p = x.segment<3>(3 * i);
    const Vec3 to_axis = Vec3(0.0, -p.y(), radius - p.z()).normalized();
    CHECK(n[i].dot(to_axis) == Approx(1.0).epsilon(1e-3));
  }
}

TEST_CASE("stage age counts from the scan before the clamps last moved", "[diagnosis]") {
  twin::Trial trial;
  trial.stages = {stage(0.0, 0.0), stage(100.0, 0.2), stage(130.0, 0.2), stage(400.0, 0.3)};
  CHECK(std::isnan(twin::diagnosis::stage_age_s(trial, 0)));  // placed at an unknown time
  CHECK(twin::diagnosis::stage_age_s(trial, 1) == Approx(100.0));
  CHECK(twin::diagnosis::stage_age_s(trial, 2) == Approx(130.0));  // clamps still since stage 2's move
  CHECK(twin::diagnosis::stage_age_s(trial, 3) == Approx(270.0));
  trial.stages[2].time_s.reset();
  CHECK(std::isnan(twin::diagnosis::stage_age_s(trial, 2)));
  CHECK(std::isnan(twin::diagnosis::stage_age_s(trial, 3)));  // needs the time of the scan before its move
  // Releasing a clamp is a move.
  trial.stages = {stage(0.0, 0.0), stage(50.0, 0.0, false)};
  CHECK(twin::diagnosis::stage_age_s(trial, 1) == Approx(50.0));
}

TEST_CASE("stage load is the highest clamp's lift over the first stage's mean height", "[diagnosis]") {
  twin::Trial trial;
  trial.stages = {stage(std::nullopt, 0.0), stage(std::nullopt, 0.25), stage(std::nullopt, -0.1, false)};
  CHECK(twin::diagnosis::stage_load_m(trial, 0) == Approx(0.0));
  CHECK(twin::diagnosis::stage_load_m(trial, 1) == Approx(0.25));
  CHECK(twin::diagnosis::stage_load_m(trial, 2) == Approx(-0.1));
}
