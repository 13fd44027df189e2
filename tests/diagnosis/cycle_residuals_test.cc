// The residual field of a cell run (twin/diagnosis/cycle_residuals.h) on made-up cycles: a sheet
// hanging in a vertical plane, tracked with 0.5 mm noise; in some cycles the tracked sheet has a
// 6 mm bulge the prediction lacks. The analysis must flag those cycles and only those, the
// ages must follow the clamp moves, and bad cycles must be refused by name.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "twin/diagnosis/cycle_residuals.h"
#include "twin/diagnosis/residual_analysis.h"

namespace dx = twin::diagnosis;

namespace {

const twin::SheetMesh& mesh() {
  static const twin::SheetMesh m = twin::make_rectangular_sheet(1.0, 0.8, 0.05);
  return m;
}

// The sheet in the plane y = 0, hanging from z = 1.5 m, shifted by `lift_m` up.
twin::VecX hanging(double lift_m) {
  twin::VecX x(3 * mesh().vertex_count());
  for (int v = 0; v < mesh().vertex_count(); ++v) {
    const twin::Vec2& uv = mesh().rest_uv[v];
    x.segment<3>(3 * v) = twin::Vec3(uv.x(), 0.0, 1.5 + lift_m - uv.y());
  }
  return x;
}

const std::vector<twin::ClampSpec> kClamps = {{"left", {0.1, 0.75}, 0.02}, {"right", {0.9, 0.75}, 0.02}};

// Cycles at 10 Hz; the clamps lift 5 cm at cycle 4; cycles in [bulge_from, bulge_to) carry a
// bulge of 6 mm along y (the sheet normal) around (0.3, 0.3) m of material.
std::vector<dx::SheetCycle> cycles(int count, int bulge_from, int bulge_to) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5e-3);
  std::vector<dx::SheetCycle> out;
  for (int k = 0; k < count; ++k) {
    dx::SheetCycle c;
    c.cycle_id = 100 + k;
    c.time_s = 0.1 * k;
    c.predicted_m = hanging(k >= 4 ? 0.05 : 0.0);
    c.observed_m = c.predicted_m;
    c.seen.assign(mesh().vertex_count(), true);
    for (int v = 0; v < mesh().vertex_count(); ++v) {
      if (v % 7 == 3) c.seen[v] = false;  // hidden from the cameras
      for (int i = 0; i < 3; ++i) c.observed_m(3 * v + i) += noise(rng);
      const double d2 = (mesh().rest_uv[v] - twin::Vec2(0.3, 0.3)).squaredNorm();
      if (k >= bulge_from && k < bulge_to) c.observed_m(3 * v + 1) += 6e-3 * std::exp(-d2 / (2 * 0.08 * 0.08));
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

TEST_CASE("a bulge the twin lacks is found in its cycles and region, and nowhere else", "[diagnosis][cell_log]") {
  const std::vector<dx::SheetCycle> run = cycles(12, 7, 10);
  dx::ResidualField field;
  dx::add_cycle_residuals(field, mesh(), kClamps, run, "run");
  REQUIRE(field.stages.size() == 12);
  CHECK(field.stages[7].label == "run/107");
  int seen = 0;
  for (int v = 0; v < mesh().vertex_count(); ++v) seen += v % 7 == 3 ? 0 : 1;
  CHECK(field.stages[0].samples == seen);
  const dx::ResidualAnalysis a = dx::analyse_residuals(field, 0.5e-3);
  for (int s = 0; s < 12; ++s) {
    INFO("cycle " << field.stages[s].id);
    CHECK(a.stages[s].test.significant == (s >= 7 && s < 10));
  }
  // The bulge sits at u 0.3, v 0.3 of a 1.0 x 0.8 sheet: region row 1 (v), column 0 or 1 (u).
  bool found = false;
  for (const dx::RegionResult& r : a.stages[8].regions) {
    if (r.test.significant) {
      found |= r.min_uv_m.x() <= 0.3 && r.max_uv_m.x() >= 0.3 && r.min_uv_m.y() <= 0.3 && r.max_uv_m.y() >= 0.3;
    }
  }
  CHECK(found);
  // Samples carry the material position and the residual along the normal (the plane's normal is y).
  const dx::ResidualSample& s0 = field.samples.front();
  CHECK(std::abs(std::abs(s0.normal.y()) - 1.0) < 1e-9);
  CHECK(s0.uv_m == mesh().rest_uv[s0.marker]);
}

TEST_CASE("cycle ages count from the last clamp move, loads from the first cycle's clamps", "[diagnosis][cell_log]") {
  const std::vector<dx::SheetCycle> run = cycles(8, 99, 99);
  dx::ResidualField field;
  dx::add_cycle_residuals(field, mesh(), kClamps, run, "run", {0, 3, 4, 7});
  REQUIRE(field.stages.size() == 4);
  CHECK(std::isnan(field.stages[0].age_s));  // no move seen yet
  CHECK(std::isnan(field.stages[1].age_s));
  CHECK(field.stages[2].age_s == Approx(0.0).margin(1e-12));  // cycle 4: the clamps just moved
  CHECK(field.stages[3].age_s == Approx(0.3));                // cycle 7, 0.3 s later
  CHECK(field.stages[0].load_m == Approx(0.0).margin(1e-9));
  CHECK(field.stages[3].load_m == Approx(0.05));
  CHECK(field.stages[3].trial_stage == 7);
}

TEST_CASE("cycles that do not match the mesh are refused with their id", "[diagnosis][cell_log]") {
  std::vector<dx::SheetCycle> run = cycles(3, 99, 99);
  run[1].predicted_m.conservativeResize(run[1].predicted_m.size() - 3);
  dx::ResidualField field;
  CHECK_THROWS_WITH(dx::add_cycle_residuals(field, mesh(), kClamps, run, "run"), Catch::Contains("cycle 101"));
  run = cycles(3, 99, 99);
  run[2].observed_m(0) = NAN;
  CHECK_THROWS_WITH(dx::add_cycle_residuals(field, mesh(), kClamps, run, "run"),
                    Catch::Contains("cycle 102") && Catch::Contains("vertex 0"));
  CHECK_THROWS_AS(dx::add_cycle_residuals(field, mesh(), kClamps, run, "run", {2, 1}), std::invalid_argument);
}

TEST_CASE("a long run is sampled evenly, first and last cycle included", "[diagnosis][cell_log]") {
  CHECK(dx::spread_cycles(5, 10) == std::vector<std::size_t>{0, 1, 2, 3, 4});
  CHECK(dx::spread_cycles(100, 5) == std::vector<std::size_t>{0, 25, 50, 74, 99});
  CHECK(dx::spread_cycles(0, 5).empty());
  CHECK(dx::spread_cycles(7, 1) == std::vector<std::size_t>{0});
}
