// Which earlier evaluations a material is continued from (twin/trials/continuation_start.h).
#include <catch2/catch.hpp>

#include <cmath>

#include "twin/trials/continuation_start.h"

namespace {

Eigen::VectorXd at(double a, double b) { return Eigen::Vector2d(a, b); }

const double kOneStep = std::log(1.5);
const double kReach = 24 * kOneStep;

}  // namespace

TEST_CASE("a shorter step is continued from the rejected point and from the accepted one", "[twin][continuation]") {
  // Levenberg-Marquardt accepted y (good fit), rejected y + s (its continuation crossed onto a
  // worse branch) and now tries y + s/2, nearer the rejected point.
  const std::vector<twin::EvaluatedMaterial> evaluated = {{at(0.0, 0.0), 1.0}, {at(0.3, 0.0), 5.0}};
  const twin::ContinuationStarts s = twin::continuation_starts(evaluated, at(0.2, 0.0), kOneStep, kReach);
  REQUIRE(s.nearest);
  CHECK(*s.nearest == 1);
  REQUIRE(s.best_nearby);
  CHECK(*s.best_nearby == 0);
}

TEST_CASE("one start when the nearest fits best or nothing else is within one step", "[twin][continuation]") {
  const std::vector<twin::EvaluatedMaterial> nearest_best = {{at(0.0, 0.0), 5.0}, {at(0.3, 0.0), 1.0}};
  const twin::ContinuationStarts a = twin::continuation_starts(nearest_best, at(0.2, 0.0), kOneStep, kReach);
  CHECK(*a.nearest == 1);
  CHECK_FALSE(a.best_nearby);
  const std::vector<twin::EvaluatedMaterial> far = {{at(0.0, 0.0), 1.0}, {at(1.5, 0.0), 5.0}};
  const twin::ContinuationStarts b = twin::continuation_starts(far, at(1.2, 0.0), kOneStep, kReach);
  CHECK(*b.nearest == 1);
  CHECK_FALSE(b.best_nearby);
  // Of two equally near (one material continued, and simulated afresh), the better fit.
  const std::vector<twin::EvaluatedMaterial> twice = {{at(0.0, 0.0), 3.0}, {at(0.0, 0.0), 2.0}};
  const twin::ContinuationStarts c = twin::continuation_starts(twice, at(1.0, 1.0), kOneStep, kReach);
  CHECK(*c.nearest == 1);
  CHECK_FALSE(c.best_nearby);
}

TEST_CASE("nothing is continued from too far away or from another parameter list", "[twin][continuation]") {
  const std::vector<twin::EvaluatedMaterial> evaluated = {{at(0.0, 0.0), 1.0}, {Eigen::Vector3d(0.1, 0.0, 0.0), 0.5}};
  CHECK_FALSE(twin::continuation_starts(evaluated, at(0.0, kReach + 0.1), kOneStep, kReach).nearest);
  const twin::ContinuationStarts s = twin::continuation_starts(evaluated, at(0.1, 0.0), kOneStep, kReach);
  CHECK(*s.nearest == 0);
  CHECK_FALSE(s.best_nearby);
  CHECK_FALSE(twin::continuation_starts({}, at(0.0, 0.0), kOneStep, kReach).nearest);
}
