#include <catch2/catch.hpp>

#include <cmath>

#include "tests/diagnosis/synthetic_field.h"
#include "twin/diagnosis/residual_analysis.h"

using namespace diagnosis_test;
using twin::diagnosis::analyse_residuals;
using twin::diagnosis::ResidualAnalysis;

namespace {

const twin::diagnosis::Correlation& correlation(const ResidualAnalysis& a, const std::string& quantity) {
  for (const auto& c : a.correlations)
    if (c.quantity == quantity) return c;
  FAIL("no correlation for " << quantity);
  throw;
}

}  // namespace

TEST_CASE("pure noise at its own sigma is not significant, and false alarms are rare", "[diagnosis]") {
  constexpr int kRuns = 200;
  int false_alarms = 0, notable_structure = 0;
  for (int run = 0; run < kRuns; ++run) {
    SyntheticOptions o;
    o.seed = 1000 + run;
    o.stages = 3;
    // Against the noise alone (no tolerated model error): the tests' own calibration.
    twin::diagnosis::AnalysisOptions exact;
    exact.tolerated_model_error = 0.0;
    const ResidualAnalysis a = analyse_residuals(synthetic_field(o, no_error), o.sigma_m, exact);
    false_alarms += a.any_significant() ? 1 : 0;
    for (const auto& c : a.correlations) notable_structure += c.notable ? 1 : 0;
    if (run == 0) {
      CHECK(a.tests == 1 + 3 + 3 * 9);
      CHECK(a.overall.rms_m == Approx(o.sigma_m).epsilon(0.05));
      CHECK(a.sentences.front().find("consistent with noise") != std::string::npos);
      CHECK(a.direction.direction.empty());
    }
  }
  // Bonferroni keeps the family-wise rate at or below alpha = 5 % (10 of 200 expected at most).
  INFO(false_alarms << " of " << kRuns << " pure-noise fields flagged");
  CHECK(false_alarms <= 16);
  // Each correlation is tested at 5 %: four per run.
  CHECK(notable_structure <= 0.1 * 4 * kRuns);
}

TEST_CASE("a model error within the tolerance is not flagged, but tested against the noise alone it is", "[diagnosis]") {
  SyntheticOptions o;
  // A smooth error of RMS ~0.4 sigma per coordinate: z = 0.4 sigma sqrt(3) sin(...) over the sheet.
  const auto small = [](const Vec2& uv, int) { return Vec3(0, 0, 0.4 * 0.3e-3 * std::sqrt(6.0) * std::sin(6.0 * uv.x())); };
  const auto field = synthetic_field(o, small);
  CHECK_FALSE(analyse_residuals(field, o.sigma_m).overall.significant);
  twin::diagnosis::AnalysisOptions exact;
  exact.tolerated_model_error = 0.0;
  CHECK(analyse_residuals(field, o.sigma_m, exact).overall.significant);
}

TEST_CASE("noise twice the assumed sigma is significant everywhere", "[diagnosis]") {
  SyntheticOptions o;
  o.sigma_m = 0.6e-3;
  const ResidualAnalysis a = analyse_residuals(synthetic_field(o, no_error), 0.3e-3);
  CHECK(a.overall.significant);
  CHECK(a.significant_stage_count() == o.stages);
}

TEST_CASE("a field growing along u is reported as along u (weft), and one along v as warp", "[diagnosis]") {
  SyntheticOptions o;
  const auto along_u = [](const Vec2& uv, int s) { return Vec3(0, 0, 1.5e-3 * (1 + s) * (uv.x() - 0.585) * (uv.x() - 0.585) / 0.34); };
  const ResidualAnalysis a = analyse_residuals(synthetic_field(o, along_u), o.sigma_m);
  CHECK(a.overall.significant);
  CHECK(a.direction.direction == "u");
  CHECK(a.direction.explained_by_u > 0.5);
  CHECK(a.direction.explained_by_v < 0.1);
  bool said = false;
  for (const auto& s : a.sentences) said = said || s.find("along u, the weft") != std::string::npos;
  CHECK(said);

  const auto along_v = [](const Vec2& uv, int) { return Vec3(0, 0, 2e-3 * uv.y()); };
  const ResidualAnalysis b = analyse_residuals(synthetic_field(o, along_v), o.sigma_m);
  CHECK(b.direction.direction == "v");

  const auto both = [](const Vec2& uv, int) { return Vec3(0, 0, 2e-3 * (uv.x() / 1.17 + uv.y() / 0.975)); };
  CHECK(analyse_residuals(synthetic_field(o, both), o.sigma_m).direction.direction.empty());
}

TEST_CASE("one bad region in one stage is flagged, and only it", "[diagnosis]") {
  SyntheticOptions o;
  // Stage 3 (index 2), region u high / v low: the markers there are off by 1 mm along the normal.
  const auto bad = [](const Vec2& uv, int s) {
    return s == 2 && uv.x() > 0.78 && uv.y() < 0.325 ? Vec3(0, 0, 1e-3) : Vec3::Zero();
  };
  const ResidualAnalysis a = analyse_residuals(synthetic_field(o, bad), o.sigma_m);
  REQUIRE(a.stages.size() == 4);
  CHECK(a.stages[2].test.significant);
  CHECK(a.significant_stage_count() == 1);
  CHECK(a.significant_region_count() == 1);
  const auto& region = a.stages[2].regions[0 * 3 + 2];  // row 0 (v low), col 2 (u high)
  CHECK(region.row == 0);
  CHECK(region.col == 2);
  CHECK(region.test.significant);
  bool named = false;
  for (const auto& s : a.sentences) named = named || s.find("synthetic/3 u high / v low") != std::string::npos;
  CHECK(named);
}

TEST_CASE("an error that fades away from the clamp correlates with clamp distance", "[diagnosis]") {
  SyntheticOptions o;
  const auto near_clamp = [](const Vec2& uv, int) {
    return Vec3(0, 0, 2e-3 * std::exp(-(uv - Vec2(0.0, 0.975)).norm() / 0.3));
  };
  const ResidualAnalysis a = analyse_residuals(synthetic_field(o, near_clamp), o.sigma_m);
  const auto& c = correlation(a, "clamp distance");
  CHECK(c.notable);
  CHECK(c.r < -0.3);
  CHECK_FALSE(correlation(a, "curvature").notable);  // constant in the synthetic field
  CHECK(correlation(a, "curvature").samples == 0);
}

TEST_CASE("an error that grows with the stage load correlates with it over stages", "[diagnosis]") {
  SyntheticOptions o;
  o.stages = 6;  // load 0, 0.1, ..., 0.5 m
  const auto loaded = [](const Vec2&, int s) { return Vec3(0, 0, 0.4e-3 * s); };
  const ResidualAnalysis a = analyse_residuals(synthetic_field(o, loaded), o.sigma_m);
  const auto& c = correlation(a, "stage load");
  CHECK(c.samples == 6);
  CHECK(c.r > 0.9);
  CHECK(c.notable);
  CHECK(correlation(a, "stage age").samples == 0);  // no times
}

TEST_CASE("bad analysis input is an error naming what is wrong", "[diagnosis]") {
  SyntheticOptions o;
  const auto field = synthetic_field(o, no_error);
  CHECK_THROWS_WITH(analyse_residuals(field, 0.0), Catch::Contains("sigma"));
  CHECK_THROWS_WITH(analyse_residuals(twin::diagnosis::ResidualField{}, 1e-3), Catch::Contains("no samples"));
}
