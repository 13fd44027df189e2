// End to end on a scanner-lab trial (sim_hw/scanner_lab.h): the lab's reference and the twin use
// the same 300-triangle mesh, so at the truth material the residual is the lab's scanner noise
// (0.3 mm per coordinate) plus the clamp probe's small noise, and nothing should be flagged;
// with twice the bending rigidity the twin is wrong and the analysis must say so.
#include <catch2/catch.hpp>

#include <filesystem>

#include "sim_hw/scanner_lab.h"
#include "tests/diagnosis/svg_check.h"
#include "tests/support/temp_dir.h"
#include "twin/diagnosis/diagnosis_report.h"
#include "twin/diagnosis/noise_estimate.h"
#include "twin/diagnosis/residual_analysis.h"
#include "twin/diagnosis/refit.h"
#include "twin/trials/discretisation_check.h"
#include "twin/trials/identification.h"
#include "twin/trials/stage_age.h"
#include "tests/support/uniform_lab_config.h"

namespace dx = twin::diagnosis;

namespace {

constexpr int kTriangles = 300;

const sim_hw::LabTrial& lab_trial() {
  static const sim_hw::LabTrial lab = [] {
    return sim_hw::make_lab_trial(testing_support::uniform_lab_config(11, kTriangles));
  }();
  return lab;
}

struct Evaluated {
  dx::ResidualField field;
  dx::ResidualAnalysis given, estimated;
  dx::NoiseEstimate noise;
};

Evaluated evaluate(const twin::Material& material) {
  twin::TrialEvaluator evaluator(lab_trial().trial, kTriangles, material);
  const twin::TrialFit fit = evaluator.evaluate(material, {});
  INFO(fit.failure);
  REQUIRE(fit.usable());
  Evaluated e;
  dx::add_trial_residuals(e.field, evaluator, fit, "lab");
  e.given = dx::analyse_residuals(e.field, 0.3e-3);
  e.noise = dx::estimate_noise(e.field);
  e.estimated = dx::analyse_residuals(e.field, e.noise.sigma_m);
  return e;
}

twin::Material doubled_bending() {
  twin::Material m = lab_trial().truth;
  m.bending_rigidity_u_Nm *= 2.0;
  m.bending_rigidity_v_Nm *= 2.0;
  return m;
}

}  // namespace

TEST_CASE("at the lab's truth the residual is noise, with sigma given or estimated", "[diagnosis][lab]") {
  const Evaluated e = evaluate(lab_trial().truth);
  REQUIRE_FALSE(e.field.stages.empty());
  int seen = 0;
  for (const auto& stage : lab_trial().trial.stages) seen += stage.observed.has_markers() ? stage.observed.seen_marker_count() : 0;
  CHECK(static_cast<int>(e.field.samples.size()) == seen);
  for (const auto& s : e.given.sentences) UNSCOPED_INFO(s);
  CHECK_FALSE(e.given.any_significant());
  CHECK(e.noise.sigma_m == Approx(0.3e-3).epsilon(0.15));
  CHECK_FALSE(e.estimated.any_significant());
  CHECK(e.given.sentences.size() == 1);  // "consistent with noise", no structure read into it
  // The same markers as a list (no grid): the same estimate.
  dx::ResidualField listed = e.field;
  listed.trials[0].grid_rows.reset();
  listed.trials[0].grid_cols.reset();
  const dx::NoiseEstimate from_list = dx::estimate_noise(listed);
  CHECK(from_list.method == e.noise.method);
  CHECK(from_list.sigma_m == Approx(e.noise.sigma_m).epsilon(1e-12));
  // What the structure measures see on a real field: finite and in range.
  for (const auto& s : e.field.samples) {
    CHECK(s.normal.norm() == Approx(1.0));
    CHECK(std::isfinite(s.curvature_1_m));
    CHECK(s.clamp_distance_m >= 0.0);
  }
}

TEST_CASE("with twice the bending rigidity the residual is significant, and the report shows it", "[diagnosis][lab]") {
  const Evaluated wrong = evaluate(doubled_bending());
  for (const auto& s : wrong.given.sentences) UNSCOPED_INFO(s);
  CHECK(wrong.given.overall.significant);
  CHECK(wrong.given.significant_stage_count() >= 1);
  // The model error (RMS ~3.5 mm per coordinate) is smooth between the twin's mesh edges, so
  // the estimate still mostly sees the noise, not the error (measured: 18 % high).
  CHECK(wrong.noise.sigma_m == Approx(0.3e-3).epsilon(0.25));
  CHECK(wrong.given.overall.rms_m > 10 * wrong.noise.sigma_m / 1.25);
  CHECK(wrong.estimated.overall.significant);

  const Evaluated right = evaluate(lab_trial().truth);
  dx::ReportData data;
  data.verdict_line = "test: twice the bending, then the truth";
  data.after_label = "at the truth";
  data.noise_floor_m = 0.3e-3;
  dx::ReportPhase phase{"train", wrong.field, wrong.given, right.field, right.given};
  data.phases.push_back(phase);
  testing_support::TempDir dir("diagnosis_lab");
  dx::write_report(data, dir / "report");
  for (std::size_t s = 0; s < wrong.field.stages.size(); ++s) {
    const std::string svg =
        diagnosis_test::read_text((dir / "report" / "figures" / ("train_stage_" + std::to_string(s + 1) + ".svg")).string());
    CHECK(diagnosis_test::svg_problem(svg).empty());
    CHECK(diagnosis_test::count_of(svg, "<circle") == wrong.field.stages[s].samples + right.field.stages[s].samples);
  }
  CHECK(dx::terminal_summary(data).find("at the truth") != std::string::npos);
}

TEST_CASE("an unusable fit cannot make a residual field, and the error names the trial", "[diagnosis][lab]") {
  twin::TrialEvaluator evaluator(lab_trial().trial, kTriangles, lab_trial().truth);
  twin::TrialFit failed;
  failed.failure = "stage 3: iteration limit";
  dx::ResidualField field;
  CHECK_THROWS_WITH(dx::add_trial_residuals(field, evaluator, failed, "lab_a"),
                    Catch::Contains("lab_a") && Catch::Contains("stage 3: iteration limit"));
  CHECK(field.trials.empty());
  CHECK_THROWS_WITH(dx::analyse_residuals(field, 0.3e-3), Catch::Contains("no samples"));
}

// The independent lab (sim_hw/real_sheet): a sheet the twin does not share, folding between its
// 17 x 17 markers, with a known noise. The field is the observed markers alone (the residual
// against the noise-free truth is pure noise, a check of the variance factors).
TEST_CASE("on an independent-lab trial the noise estimate is the same for a grid and a list of markers",
          "[diagnosis][lab]") {
  sim_hw::ScannerLabConfig config;
  config.seed = 3;
  config.truth_model = sim_hw::TruthModel::kIndependent;
  config.grid_spacing_m = 0.05;  // coarse: seconds, not minutes; it still folds
  config.path_grid_spacing_m = 0.05;
  config.marker_noise_m = 0.5e-3;
  config.raw_scans = false;
  const sim_hw::LabTrial lab = sim_hw::make_lab_trial(config);
  REQUIRE(lab.trial.marker_grid_rows.has_value());
  dx::ResidualField grid;
  dx::FieldTrial trial;
  trial.name = "independent";
  trial.sheet_max_uv_m = twin::Vec2(lab.trial.sheet.width_m, lab.trial.sheet.height_m);
  trial.grid_rows = lab.trial.marker_grid_rows;
  trial.grid_cols = lab.trial.marker_grid_cols;
  trial.marker_count = static_cast<int>(lab.trial.marker_uv_m.size());
  grid.trials.push_back(trial);
  for (std::size_t s = 0; s < lab.trial.stages.size(); ++s) {
    dx::FieldStage stage;
    stage.trial_stage = static_cast<int>(s);
    for (std::size_t m = 0; m < lab.trial.marker_uv_m.size(); ++m) {
      const twin::Vec3& observed = lab.trial.stages[s].observed.markers_m[m];
      if (!observed.allFinite()) continue;
      dx::ResidualSample sample;
      sample.stage = static_cast<int>(grid.stages.size());
      sample.marker = static_cast<int>(m);
      sample.uv_m = lab.trial.marker_uv_m[m];
      sample.observed_m = observed;
      sample.residual_m = observed - lab.true_markers_m[s][m];
      grid.samples.push_back(sample);
      ++stage.samples;
    }
    grid.stages.push_back(stage);
  }
  dx::ResidualField listed = grid;
  listed.trials[0].grid_rows.reset();
  listed.trials[0].grid_cols.reset();
  const dx::NoiseEstimate a = dx::estimate_noise(grid), b = dx::estimate_noise(listed);
  INFO("from observations " << a.from_observations_m << " m, from pure-noise residuals " << a.from_residuals_m << " m");
  CHECK(a.from_observations_m == b.from_observations_m);
  CHECK(a.from_residuals_m == b.from_residuals_m);
  CHECK(a.from_residuals_m == Approx(config.marker_noise_m).epsilon(0.1));
  // From the folded sheet alone it reads high (noise_estimate.h, LIMIT: 1.5x measured here; the
  // neighbour planes used for lists before read several times the noise), but never low.
  CHECK(a.from_observations_m >= 0.9 * config.marker_noise_m);
  CHECK(a.from_observations_m <= 2.0 * config.marker_noise_m);
}

// The lab scanning each pose three times (a user checking repeatability): the stages of a pose
// share its probed clamp poses and the moment the clamps stopped, the residual field groups
// them, and the noise read from the scans' differences is the lab's, where a single scan's local
// fits read the folds as noise.
TEST_CASE("on an independent-lab trial with repeated scans the noise estimate is the lab's", "[diagnosis][lab]") {
  sim_hw::ScannerLabConfig config;
  config.seed = 3;
  config.truth_model = sim_hw::TruthModel::kIndependent;
  config.grid_spacing_m = 0.05;
  config.path_grid_spacing_m = 0.05;
  config.marker_noise_m = 0.5e-3;
  config.raw_scans = false;
  config.scans_per_stage = 3;
  const sim_hw::LabTrial lab = sim_hw::make_lab_trial(config);
  REQUIRE(lab.trial.stages.size() == 15);
  CHECK(lab.trial.stages[0].id == "1a");
  CHECK(lab.trial.stages[2].id == "1c");
  CHECK(lab.trial.stages[3].id == "2a");
  for (std::size_t s = 1; s < lab.trial.stages.size(); ++s) {
    const twin::TrialStage &a = lab.trial.stages[s - 1], &b = lab.trial.stages[s];
    CHECK(*b.time_s > *a.time_s);
    const bool repeat = s % 3 != 0;
    CHECK(twin::same_clamp_poses(a, b) == repeat);
    CHECK((a.clamps_moved_at_s == b.clamps_moved_at_s) == repeat);
  }
  twin::TrialEvaluator evaluator(lab.trial, kTriangles, lab.truth);
  const twin::TrialFit fit = evaluator.evaluate(lab.truth, {});
  INFO(fit.failure);
  REQUIRE(fit.usable());
  dx::ResidualField field;
  dx::add_trial_residuals(field, evaluator, fit, "independent");
  CHECK(field.pose_groups == 5);
  for (const dx::FieldStage& stage : field.stages) CHECK(stage.pose_group == stage.trial_stage / 3);
  const dx::NoiseEstimate noise = dx::estimate_noise(field);
  INFO("repeated scans " << noise.from_repeated_scans_m << " m, observed markers " << noise.from_observations_m
                         << " m, residuals " << noise.from_residuals_m << " m");
  CHECK(noise.method == "repeated scans of one pose");
  CHECK(noise.sigma_m == Approx(config.marker_noise_m).epsilon(0.1));
  CHECK(noise.from_observations_m > noise.sigma_m);
}

// The discretisation check (twin/trials/discretisation_check.h) on trials of the twin's own model: made
// on the twin's very mesh, the residual holds none of the twin's discretisation pattern, however
// far the markers move on twice the triangles; made on a finer mesh, it holds it.
TEST_CASE("the residual holds the twin's discretisation error only when the sheet was not made on its mesh",
          "[diagnosis][lab]") {
  const auto check_on = [](int reference_triangles) {
    const sim_hw::LabTrial lab =
        sim_hw::make_lab_trial(testing_support::uniform_lab_config(11, reference_triangles));
    twin::TrialEvaluator evaluator(lab.trial, kTriangles, lab.truth);
    twin::TwinMeshSpec mesh;
    mesh.triangles = kTriangles;
    return twin::check_discretisation({&evaluator}, mesh, lab.truth, {});
  };
  const twin::DiscretisationCheck own = check_on(kTriangles), finer = check_on(4 * kTriangles);
  REQUIRE(own.usable());
  REQUIRE(finer.usable());
  INFO("own mesh: moved " << own.rms_m << " m, pattern in residual " << own.pattern_in_residual << ", held "
                          << own.error_in_residual_rms_m << " m; finer: moved " << finer.rms_m << " m, pattern "
                          << finer.pattern_in_residual << ", held " << finer.error_in_residual_rms_m << " m");
  CHECK(own.rms_m > 1e-3);  // the markers move by millimetres on twice the triangles
  CHECK(std::abs(own.pattern_in_residual) < 0.1);
  CHECK(own.error_in_residual_rms_m < 0.1 * own.rms_m);
  CHECK(finer.pattern_in_residual > 0.5);
  CHECK(finer.error_in_residual_rms_m > 0.5 * finer.rms_m);
  CHECK(own.error_pattern_m.size() > 0);
}

// Intervals widened by the shift the twin's discretisation error makes (identification.h): on a
// sheet made on a finer mesh, at the true material, every interval holds the plain one and is
// wider by the shift on each side.
TEST_CASE("the twin's discretisation error widens the intervals by the shift it makes", "[diagnosis][lab]") {
  const sim_hw::LabTrial lab = sim_hw::make_lab_trial(testing_support::uniform_lab_config(11, 4 * kTriangles));
  twin::TrialEvaluator evaluator(lab.trial, kTriangles, lab.truth);
  twin::TwinMeshSpec mesh;
  mesh.triangles = kTriangles;
  const twin::DiscretisationCheck check = twin::check_discretisation({&evaluator}, mesh, lab.truth, dx::base_parameters());
  REQUIRE(check.usable());
  const twin::VecX held = std::max(0.0, check.pattern_in_residual) * check.error_pattern_m;
  twin::IdentificationProblem problem({&evaluator}, lab.truth, dx::base_parameters());
  twin::IdentificationResult plain;
  plain.material = lab.truth;
  plain.coordinates = problem.coordinates_of(lab.truth);
  twin::IdentificationResult widened = plain;
  twin::estimate_uncertainty(problem, plain);
  twin::estimate_uncertainty(problem, widened, twin::IntervalKind::kFisher, &held);
  REQUIRE(plain.estimates.size() == 3);
  REQUIRE(widened.estimates.size() == 3);
  double largest_shift = 0.0;
  for (std::size_t j = 0; j < 3; ++j) {
    const twin::ParameterEstimate &p = plain.estimates[j], &w = widened.estimates[j];
    INFO(twin::parameter_name(p.parameter) << ": plain [" << p.lower95 << ", " << p.upper95 << "], widened ["
                                           << w.lower95 << ", " << w.upper95 << "], shift " << w.discretisation_shift);
    CHECK(p.discretisation_shift == 0.0);
    CHECK(w.lower95 <= p.lower95);
    CHECK(w.upper95 >= p.upper95);
    // The shift lies inside the widened interval around the value.
    CHECK(w.value + w.discretisation_shift >= w.lower95);
    CHECK(w.value + w.discretisation_shift <= w.upper95);
    largest_shift = std::max(largest_shift, std::abs(w.discretisation_shift / w.value));
  }
  CHECK(largest_shift > 1e-3);  // a 300-triangle twin of a sheet made on 1200 is biased
  // A vector of another length is ignored.
  twin::IdentificationResult ignored = plain;
  const twin::VecX wrong = twin::VecX::Zero(3);
  twin::estimate_uncertainty(problem, ignored, twin::IntervalKind::kFisher, &wrong);
  CHECK(ignored.estimates[0].discretisation_shift == 0.0);
  CHECK(ignored.estimates[0].upper95 == plain.estimates[0].upper95);
}
