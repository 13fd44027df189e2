#include "twin/model/bending_calibration.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace twin {
namespace {

struct Spread {
  double min = 1e300, max = 0.0;
};

Spread rigidity_spread(const SheetMesh& mesh, const std::vector<double>& k,
                       const std::vector<Hinge>& hinges, double expected) {
  Spread s;
  for (int deg = 0; deg < 180; deg += 15) {
    const double d = effective_cylinder_rigidity(mesh, hinges, k, deg * M_PI / 180.0);
    s.min = std::min(s.min, d / expected);
    s.max = std::max(s.max, d / expected);
  }
  return s;
}

TEST_CASE("calibrated hinges store the plate energy of cylinders along u and v",
          "[twin][bending]") {
  const SheetMesh mesh = make_rectangular_sheet(0.6, 0.5, 0.02);
  const auto hinges = build_hinges(mesh);
  const BendingCalibration cal(mesh, hinges);
  const auto k = cal.hinge_stiffnesses(2e-3, 5e-4);
  CHECK(effective_cylinder_rigidity(mesh, hinges, k, 0.0) == Approx(2e-3).epsilon(1e-5));
  CHECK(effective_cylinder_rigidity(mesh, hinges, k, M_PI / 2) == Approx(5e-4).epsilon(1e-5));
}

TEST_CASE("an isotropic sheet bends isotropically on the offset-row mesh", "[twin][bending]") {
  // Cylinders along u and v are exact by construction; every other direction, the diagonals
  // included, must agree too. The spread shrinks with refinement (boundary hinges are the rest).
  const double d = 1e-3;
  const std::pair<double, double> edge_and_tolerance[] = {{0.05, 0.05}, {0.02, 0.01}};
  for (auto [edge, tolerance] : edge_and_tolerance) {
    const SheetMesh mesh = make_rectangular_sheet(1.17, 0.975, edge);
    const auto hinges = build_hinges(mesh);
    const auto k = BendingCalibration(mesh, hinges).hinge_stiffnesses(d, d);
    const Spread s = rigidity_spread(mesh, k, hinges, d);
    INFO("edge " << edge << ": D(angle)/D in [" << s.min << ", " << s.max << "]");
    CHECK(s.min > 1.0 - tolerance);
    CHECK(s.max < 1.0 + tolerance);
  }
}

TEST_CASE("a right-triangle grid is visibly anisotropic even after calibration",
          "[twin][bending]") {
  // The check above must be able to fail: the same calibration on a right-triangle grid
  // matches u and v but misses the diagonals by tens of percent.
  const SheetMesh mesh = make_rectangular_sheet(1.17, 0.975, 0.03, TriangulationPattern::kRightTriangles);
  const auto hinges = build_hinges(mesh);
  const auto k = BendingCalibration(mesh, hinges).hinge_stiffnesses(1e-3, 1e-3);
  const Spread s = rigidity_spread(mesh, k, hinges, 1e-3);
  INFO("D(angle)/D in [" << s.min << ", " << s.max << "]");
  CHECK(s.max / s.min > 1.2);
}

TEST_CASE("too strong a bending anisotropy is rejected, not silently mis-modelled",
          "[twin][bending]") {
  const SheetMesh mesh = make_rectangular_sheet(0.3, 0.3, 0.02);
  const auto hinges = build_hinges(mesh);
  const BendingCalibration cal(mesh, hinges);
  CHECK_NOTHROW(cal.hinge_stiffnesses(1e-3, 3e-3));
  CHECK_THROWS_WITH(cal.hinge_stiffnesses(1e-3, 100e-3), Catch::Contains("warp/weft"));
}

}  // namespace
}  // namespace twin
