// Which earlier evaluation a material is continued from (twin/continuation_start.h).
#include <catch2/catch.hpp>

#include <cmath>

#include "twin/continuation_start.h"

namespace {

Eigen::VectorXd at(double a, double b) { return Eigen::Vector2d(a, b); }

const double kOneStep = std::log(1.5);
const double kReach = 24 * kOneStep;

}  // namespace

TEST_CASE("a shorter step continues from the accepted point, not the nearer rejected one", "[twin][continuation]") {
  // Levenberg-Marquardt accepted y (good fit), rejected y + s (its continuation crossed onto a
  // worse branch) and now tries y + s/2, nearer the rejected point.
  const std::vector<twin::EvaluatedMaterial> evaluated = {{at(0.0, 0.0), 1.0}, {at(0.3, 0.0), 5.0}};
  const auto k = twin::continuation_start(evaluated, at(0.2, 0.0), kOneStep, kReach);
  REQUIRE(k);
  CHECK(*k == 0);
}

TEST_CASE("beyond one material step the nearest evaluation is continued", "[twin][continuation]") {
  const std::vector<twin::EvaluatedMaterial> evaluated = {{at(0.0, 0.0), 1.0}, {at(1.5, 0.0), 5.0}};
  const auto k = twin::continuation_start(evaluated, at(1.2, 0.0), kOneStep, kReach);
  REQUIRE(k);
  CHECK(*k == 1);
  // Of two equally near (one material continued, and simulated afresh), the better fit.
  const std::vector<twin::EvaluatedMaterial> twice = {{at(0.0, 0.0), 3.0}, {at(0.0, 0.0), 2.0}};
  CHECK(*twin::continuation_start(twice, at(1.0, 1.0), kOneStep, kReach) == 1);
}

TEST_CASE("nothing is continued from too far away or from another parameter list", "[twin][continuation]") {
  const std::vector<twin::EvaluatedMaterial> evaluated = {{at(0.0, 0.0), 1.0}, {Eigen::Vector3d(0.1, 0.0, 0.0), 0.5}};
  CHECK_FALSE(twin::continuation_start(evaluated, at(0.0, kReach + 0.1), kOneStep, kReach));
  CHECK(*twin::continuation_start(evaluated, at(0.1, 0.0), kOneStep, kReach) == 0);
  CHECK_FALSE(twin::continuation_start({}, at(0.0, 0.0), kOneStep, kReach));
}
