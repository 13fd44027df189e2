#include <catch2/catch.hpp>

#include <cmath>

#include "tests/diagnosis/synthetic_field.h"
#include "twin/diagnosis/noise_estimate.h"

using namespace diagnosis_test;

namespace {

// A smooth model error 10x the noise: quadratic in u and v, different per stage.
Vec3 smooth(const Vec2& uv, int stage) {
  const double q = 3e-3 * (1.0 + 0.3 * stage);
  return Vec3(q * uv.x() * uv.x(), -q * uv.x() * uv.y(), q * (uv.y() * uv.y() + 0.5 * uv.x()));
}

}  // namespace

TEST_CASE("local fits recover the noise of a marker grid under a smooth field 10x larger", "[diagnosis]") {
  for (unsigned seed : {1u, 2u, 3u}) {
    SyntheticOptions o;
    o.seed = seed;
    const auto estimate = twin::diagnosis::estimate_noise(synthetic_field(o, smooth));
    INFO("seed " << seed << " sigma " << estimate.sigma_m);
    CHECK(estimate.method.find("local quartic fits") == 0);
    CHECK(estimate.sigma_m == Approx(o.sigma_m).epsilon(0.15));
    // Every coordinate of every marker but those at the edges a quartic cannot be fitted from.
    CHECK(estimate.differences_used >= 0.8 * 3 * o.rows * o.cols * o.stages);
  }
}

TEST_CASE("local fits recover the noise of markers off a grid", "[diagnosis]") {
  for (unsigned seed : {4u, 5u}) {
    SyntheticOptions o;
    o.seed = seed;
    o.grid = false;
    const auto estimate = twin::diagnosis::estimate_noise(synthetic_field(o, smooth));
    INFO("seed " << seed << " sigma " << estimate.sigma_m);
    CHECK(estimate.method.find("local quartic fits") == 0);
    CHECK(estimate.sigma_m == Approx(o.sigma_m).epsilon(0.15));
  }
}

TEST_CASE("a model error kinked at every marker is seen through by differencing the observations", "[diagnosis]") {
  SyntheticOptions o;
  // The twin's prediction kinks between markers (a coarse mesh, a large error): a zigzag of
  // 3 mm along u and along v with a period of 3.3 marker spacings. The observed sheet is smooth
  // (flat) plus noise.
  const auto zigzag = [](const Vec2& uv, int) {
    const double pu = std::fmod(uv.x() / (3.3 * 1.17 / 17), 1.0), pv = std::fmod(uv.y() / (3.3 * 0.975 / 17), 1.0);
    return Vec3(0, 0, 3e-3 * (std::abs(2.0 * pu - 1.0) + std::abs(2.0 * pv - 1.0)));
  };
  auto field = synthetic_field(o, zigzag);
  for (auto& m : field.samples) m.observed_m = Vec3(m.uv_m.x(), m.uv_m.y(), 1.0) + m.residual_m - zigzag(m.uv_m, 0);
  const auto estimate = twin::diagnosis::estimate_noise(field);
  CHECK(estimate.from_residuals_m > 1.3 * o.sigma_m);  // the median resists, but not fully
  CHECK(estimate.sigma_m == Approx(o.sigma_m).epsilon(0.15));
  CHECK(estimate.method == "local quartic fits of the observed markers");
}

TEST_CASE("a sharp error at a few markers does not inflate the estimate", "[diagnosis]") {
  SyntheticOptions o;
  // Ten times the noise within 0.15 m of the top-left corner (a clamp that grips differently).
  const auto field = synthetic_field(o, [](const Vec2& uv, int) {
    return (uv - Vec2(0.0, 0.975)).norm() < 0.15 ? Vec3(0, 0, 3e-3) : Vec3::Zero();
  });
  CHECK(twin::diagnosis::estimate_noise(field).sigma_m == Approx(o.sigma_m).epsilon(0.15));
}

TEST_CASE("too few markers to difference is an error that says so", "[diagnosis]") {
  SyntheticOptions o;
  o.rows = 2;
  o.cols = 2;
  o.stages = 1;
  CHECK_THROWS_WITH(twin::diagnosis::estimate_noise(synthetic_field(o, no_error)),
                    Catch::Contains("give the noise level"));
}
