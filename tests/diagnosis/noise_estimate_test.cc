#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "tests/diagnosis/synthetic_field.h"
#include "twin/diagnosis/model_form.h"
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

TEST_CASE("repeated scans of a pose give the noise of a sheet that folds between its markers", "[diagnosis]") {
  for (const bool grid : {true, false}) {
    SyntheticOptions o;
    o.stages = 6;  // two poses, three scans each
    o.grid = grid;
    o.seed = grid ? 7u : 8u;
    auto field = synthetic_field(o, no_error);
    for (auto& stage : field.stages) stage.pose_group = stage.trial_stage / 3;
    field.pose_groups = 2;
    // The observed sheet: crumpled at the markers' spacing (each marker up to 3 mm off any
    // smooth surface, differently per pose), and from scan to scan of a pose a smooth creep of
    // up to 2 mm.
    std::mt19937 rng(o.seed + 100);
    std::uniform_real_distribution<double> crumple(-3e-3, 3e-3);
    std::vector<Vec3> shape(2 * 17 * 17);
    for (Vec3& v : shape) v = Vec3(crumple(rng), crumple(rng), crumple(rng));
    for (auto& m : field.samples) {
      const int pose = field.stages[m.stage].trial_stage / 3, scan = field.stages[m.stage].trial_stage % 3;
      m.observed_m += shape[pose * 17 * 17 + m.marker] + Vec3(0, 0, 2e-3 * scan * (m.uv_m.x() * m.uv_m.x() + 0.5 * m.uv_m.y()));
    }
    // A marker the second scan did not see (a hand in the way) is skipped, not paired wrongly.
    field.samples.erase(field.samples.begin() + 17 * 17 + 40);
    const auto estimate = twin::diagnosis::estimate_noise(field);
    INFO((grid ? "grid" : "list") << ": repeated " << estimate.from_repeated_scans_m << " m, observations "
                                  << estimate.from_observations_m << " m");
    CHECK(estimate.method == "repeated scans of one pose");
    CHECK(estimate.sigma_m == estimate.from_repeated_scans_m);
    CHECK(estimate.sigma_m == Approx(o.sigma_m).epsilon(0.15));
    // The crumpling defeats the local fits of a single scan.
    CHECK(estimate.from_observations_m > 2.0 * o.sigma_m);
    // Three scans of a pose make two pairs (a-b, b-c) sharing scan b: the sampling error counts
    // one of them.
    CHECK(estimate.relative_standard_error ==
          Approx(1.166 / std::sqrt(estimate.differences_used / 2.0)).epsilon(0.02));
  }
}

TEST_CASE("stages of different poses are never differenced as repeated scans", "[diagnosis]") {
  SyntheticOptions o;
  auto field = synthetic_field(o, smooth);  // every stage a pose of its own (pose_group -1)
  const auto estimate = twin::diagnosis::estimate_noise(field);
  CHECK(std::isinf(estimate.from_repeated_scans_m));
  CHECK(estimate.method.find("local quartic fits") == 0);
}

TEST_CASE("a model-form misfit is located by stage and by ninth of the sheet", "[diagnosis]") {
  SyntheticOptions o;
  // 6 mm along the top-right ninth of the sheet in stage 3 only.
  const auto field = synthetic_field(o, [&](const Vec2& uv, int stage) {
    return stage == 2 && uv.x() > 0.8 && uv.y() > 0.7 ? Vec3(0, 0, 6e-3) : Vec3::Zero();
  });
  const auto where = twin::diagnosis::locate_model_form(field, 1e-3);
  REQUIRE(where.stages.size() == 1);
  CHECK(where.stages[0].label == "synthetic/3");
  REQUIRE(where.regions.size() == 1);
  CHECK(where.regions[0].row == 2);
  CHECK(where.regions[0].col == 2);
  CHECK(where.regions[0].min_uv_m.x() == Approx(0.78));
  CHECK_THAT(twin::diagnosis::describe(where), Catch::Contains("synthetic/3") && Catch::Contains("u 0.78-1.17 m"));
  // Pure noise: nothing beyond 1 mm, and the sentence says the misfit is not localised.
  const auto none = twin::diagnosis::locate_model_form(synthetic_field(o, no_error), 1e-3);
  CHECK(none.stages.empty());
  CHECK(none.regions.empty());
  CHECK_THAT(twin::diagnosis::describe(none), Catch::Contains("spread over the whole sheet"));
}
