// The robust pass of a refit (twin/diagnosis/refit.h, stage_weights.h) on a scanner-lab trial
// whose third stage was scanned 2 cm off (as a stage on another fold would be), while the
// other stages are at the noise: the pass must run, name that stage, and keep its result only
// when it fits all stages better; without the offset it must not run.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include "sim_hw/scanner_lab.h"
#include "tests/support/uniform_lab_config.h"
#include "twin/diagnosis/effect_library.h"
#include "twin/diagnosis/refit.h"

namespace dx = twin::diagnosis;

namespace {

constexpr int kRefitTriangles = 300;

const sim_hw::LabTrial& refit_lab_trial() {
  static const sim_hw::LabTrial lab = sim_hw::make_lab_trial(testing_support::uniform_lab_config(11, kRefitTriangles));
  return lab;
}

// The lab trial with stage `stage`'s markers moved `offset_m` along z.
twin::Trial with_stage_moved(int stage, double offset_m) {
  twin::Trial trial = refit_lab_trial().trial;
  for (twin::Vec3& m : trial.stages.at(stage).observed.markers_m) m.z() += offset_m;
  return trial;
}

dx::Refit refit(double offset_m) {
  const twin::Trial moved = with_stage_moved(2, offset_m);
  twin::TrialEvaluator training(moved, kRefitTriangles, refit_lab_trial().truth);
  twin::TrialEvaluator testing(refit_lab_trial().trial, kRefitTriangles, refit_lab_trial().truth);
  dx::RefitOptions options;
  options.max_evaluations = 30;
  return dx::refit_candidate(dx::find_effect("marker_mass"), {&training}, {&testing}, refit_lab_trial().truth,
                             Eigen::VectorXd(), std::nullopt, /*sigma_m=*/0.3e-3, options,
                             [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
}

}  // namespace

TEST_CASE("a refit with one stage far off runs the robust pass and keeps the better fit", "[diagnosis][robust][lab]") {
  const dx::Refit r = refit(0.02);
  INFO(r.failure);
  REQUIRE(r.usable());
  REQUIRE(r.robust.has_value());
  REQUIRE(r.robust->outliers.size() == 1);
  CHECK(r.robust->outliers[0].stage == refit_lab_trial().trial.stages[2].id);
  CHECK(r.robust->outliers[0].ratio > dx::kOutlierStageRatio);
  CHECK(r.robust->outliers[0].weight == Approx(std::pow(dx::kOutlierStageRatio / r.robust->outliers[0].ratio, 2)));
  REQUIRE(std::isfinite(r.robust->robust_m2));
  CHECK(r.robust->kept == (r.robust->robust_m2 < r.robust->least_squares_m2));
  const bool says_kept = r.result.stop_reason.find("robust refit") != std::string::npos;
  CHECK(says_kept == r.robust->kept);
}

TEST_CASE("no robust pass when no stage is far off", "[diagnosis][robust][lab]") {
  const dx::Refit r = refit(0.0);
  INFO(r.failure);
  REQUIRE(r.usable());
  CHECK_FALSE(r.robust.has_value());
}
