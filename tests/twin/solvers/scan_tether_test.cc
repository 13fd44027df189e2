// The scan tether (twin/solvers/scan_tether.h): its energy term against finite differences, and the
// homotopy ending at a true equilibrium of the untethered model.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>

#include "tests/support/term_check.h"
#include "tests/support/random_states.h"
#include "twin/mesh/observed_shape.h"
#include "twin/solvers/scan_tether.h"
#include "twin/solvers/static_solver.h"

namespace twin {
namespace {

TEST_CASE("the marker tether term matches finite differences", "[twin][energy]") {
  const SheetMesh mesh = make_rectangular_sheet(0.3, 0.2, 0.05);
  const std::vector<Vec2> uv = {{0.05, 0.05}, {0.17, 0.11}, {0.29, 0.19}, {0.1, 0.15}};
  const MaterialPointMap markers(mesh, uv);
  std::mt19937 rng(7);
  const VecX x = testing::random_deformed(mesh.rest_uv, 0.2, 0.05, rng);
  std::vector<Vec3> observed = markers.positions(x);
  for (Vec3& o : observed) o += Vec3(0.01, -0.02, 0.005);
  observed[3] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());  // not seen: no spring
  MarkerTetherTerm tether(markers, observed, mesh.vertex_count());
  tether.set_stiffness(3.0);
  CHECK(tether.element_count() == 3);
  const testing::DerivativeErrors errors = testing::term_derivative_errors(tether, x);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-6);
  CHECK(errors.hessian < 1e-6);
  // Energy: k/2 sum |r|^2 over the three seen markers, each off by the same offset.
  CHECK(tether.evaluate(x, nullptr, nullptr, HessianMode::kExact) ==
        Approx(0.5 * 3.0 * 3 * Vec3(0.01, -0.02, 0.005).squaredNorm()));
}

// The curtain both homotopy tests hang: a 0.6 x 0.4 m sheet held by two clamps along its top
// edge, 5 % closer than on the flat sheet, and a 5 x 7 grid of markers on it.
Material curtain_material() {
  Material material;
  material.surface_density_kg_m2 = 0.3;
  material.bending_rigidity_u_Nm = material.bending_rigidity_v_Nm = 1e-3;
  return material;
}
SheetMesh curtain_mesh() { return make_rectangular_sheet(0.6, 0.4, 0.04); }
const std::vector<ClampSpec> kCurtainClamps = {{"A", Vec2(0.02, 0.38), 0.015}, {"B", Vec2(0.58, 0.38), 0.015}};
// The clamps' poses, the jaws turned with the sheet as placed.
std::vector<ClampPose> curtain_poses(const SheetPlacement& placement) {
  std::vector<ClampPose> poses(2);
  poses[0].position_m = placement.to_world(Vec2(0.035, 0.38));
  poses[1].position_m = placement.to_world(Vec2(0.565, 0.38));
  for (ClampPose& p : poses) p.rotation = placement.rotation;
  return poses;
}
std::vector<Vec2> curtain_marker_uv() {
  std::vector<Vec2> uv;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 7; ++c) uv.push_back(Vec2(0.03 + c * 0.09, 0.03 + r * 0.08));
  }
  return uv;
}

TEST_CASE("equilibrium from a scan ends at an equilibrium of the model near the scan", "[twin][physics]") {
  const ShellModel model(curtain_mesh(), curtain_material());
  const ClampSet clamps(model.mesh(), kCurtainClamps);
  SheetPlacement placement;  // level: the sheet hangs in a curtain
  placement.origin_m = Vec3(0, 0, 1.0);
  const std::vector<ClampPose> poses = curtain_poses(placement);
  VecX reference = place_flat(model.mesh(), placement);
  StaticSolver statics(model);
  REQUIRE(statics.solve(clamps, poses, reference).usable());

  // "Scan" the reference: markers on a grid, 0.3 mm noise.
  const std::vector<Vec2> uv = curtain_marker_uv();
  const MaterialPointMap markers(model.mesh(), uv);
  std::vector<Vec3> observed = markers.positions(reference);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.3e-3);
  for (Vec3& o : observed) o += Vec3(noise(rng), noise(rng), noise(rng));

  VecX x = shape_from_markers(model.mesh(), uv, observed);
  const SolveReport report = equilibrium_from_scan(model, clamps, poses, markers, observed, x);
  INFO(report.brief());
  REQUIRE(report.usable());
  CHECK(report.residual < 1e-8);  // the last solve has no springs: an equilibrium of the model
  // ... and the same one the scanned sheet was in.
  CHECK((x - reference).cwiseAbs().maxCoeff() < 2e-3);
}

TEST_CASE("equilibrium from a scan does not end on an unstable equilibrium", "[twin][physics]") {
  // A sheet hanging in a vertical plane from two clamps 5 % closer than on the flat sheet: the
  // top edge is compressed between them. The planar shape is an equilibrium (every force lies in
  // the plane), but an unstable one: out of the plane the compression beats the bending
  // stiffness. A scan of exactly that shape, without noise, lets the springs go in the plane, and
  // the last solve stops there; it must be reported as unusable, not returned.
  const ShellModel model(curtain_mesh(), curtain_material());
  const ClampSet clamps(model.mesh(), kCurtainClamps);
  SheetPlacement placement;  // u along x, v up along z, the sheet's normal along -y
  placement.origin_m = Vec3(0, 0, 1.0);
  placement.rotation.col(0) = Vec3(1, 0, 0);
  placement.rotation.col(1) = Vec3(0, 0, 1);
  placement.rotation.col(2) = Vec3(0, -1, 0);
  const std::vector<ClampPose> poses = curtain_poses(placement);
  VecX planar = place_flat(model.mesh(), placement);
  StaticSolver statics(model);
  REQUIRE(statics.solve(clamps, poses, planar).usable());
  for (int i = 0; i < model.vertex_count(); ++i) REQUIRE(std::abs(planar(3 * i + 1)) < 1e-9);  // still planar

  const std::vector<Vec2> uv = curtain_marker_uv();
  const MaterialPointMap markers(model.mesh(), uv);
  const std::vector<Vec3> observed = markers.positions(planar);
  VecX x = planar;
  const SolveReport report = equilibrium_from_scan(model, clamps, poses, markers, observed, x);
  INFO(report.brief());
  CHECK_FALSE(report.usable());
  CHECK(report.message.find("unstable") != std::string::npos);
  CHECK(x == planar);  // on failure x is unchanged

  // The same sheet scanned bowed a little out of its plane lets go onto a stable equilibrium.
  std::vector<Vec3> bowed = observed;
  for (std::size_t m = 0; m < uv.size(); ++m) bowed[m].y() += 0.01 * std::sin(M_PI * uv[m].x() / 0.6);
  x = planar;
  const SolveReport stable = equilibrium_from_scan(model, clamps, poses, markers, bowed, x);
  INFO(stable.brief());
  CHECK(stable.usable());
  double out_of_plane_m = 0.0;
  for (int i = 0; i < model.vertex_count(); ++i) out_of_plane_m = std::max(out_of_plane_m, std::abs(x(3 * i + 1)));
  CHECK(out_of_plane_m > 1e-3);  // buckled out of the plane
}

}  // namespace
}  // namespace twin
