// The bending effects through identification with no code change: lab trials whose reference
// sheet has a roll set (rest curvature) or bending stiffening (the lab simulates them with the
// same ShellModel, from the material), identified by the gradient path starting from the effect
// absent. As in identification_test.cc the lab's reference and the twin share the 300-triangle
// mesh, so the gap is scanner noise plus the effect; the other parameters are held at the truth.
// Also: the adjoint gradient in the effect's parameter at the null value (what the discrepancy
// workflow's score test uses) against finite differences of the re-simulated trial.

#include <catch2/catch.hpp>

#include <cmath>

#include "sim_hw/lab_materials.h"
#include "sim_hw/scanner_lab.h"
#include "twin/trials/identification.h"
#include "tests/support/uniform_lab_config.h"

namespace {

using twin::MaterialParameter;

constexpr int kTriangles = 300;

sim_hw::LabTrial lab_trial_with(const twin::ModelEffects& effects) {
  sim_hw::ScannerLabConfig config = testing_support::uniform_lab_config(11, kTriangles);
  twin::Material truth = sim_hw::lab_specimen(config.specimen).truth;
  truth.effects = effects;
  config.material_override = truth;
  return sim_hw::make_lab_trial(config);
}

void check_recovered(const sim_hw::LabTrial& lab, const std::vector<MaterialParameter>& parameters,
                     double tolerance) {
  twin::Material start = lab.truth;
  start.effects = twin::ModelEffects{};
  twin::TrialEvaluator evaluator(lab.trial, kTriangles, start);

  // The adjoint gradient at the effect's absence against a forward difference (one-sided,
  // second order: stiffening cannot go below 0).
  const twin::TrialFit fit = evaluator.evaluate(start, parameters, twin::Derivatives::kGradient);
  INFO(fit.failure);
  REQUIRE(fit.usable());
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    const double h = 1e-3 * twin::parameter_scale(parameters[j]).scale;
    auto sum_squares = [&](double value) {
      twin::Material m = start;
      twin::set_parameter(m, parameters[j], value);
      const twin::TrialFit f = evaluator.evaluate(m, parameters);
      REQUIRE(f.usable());
      return f.sum_squares_m2;
    };
    const double fd = (-3.0 * fit.sum_squares_m2 + 4.0 * sum_squares(h) - sum_squares(2.0 * h)) /
                      (2.0 * h) * twin::parameter_scale(parameters[j]).scale;
    INFO(twin::parameter_name(parameters[j]) << " at 0: d(sum of squares)/dy adjoint "
                                             << fit.coordinate_gradient(j) << ", finite difference " << fd);
    CHECK(fit.coordinate_gradient(j) == Approx(fd).epsilon(1e-2));
    CHECK(fit.coordinate_gradient(j) < 0.0);  // the effect is missing: adding it helps
  }

  twin::IdentificationProblem problem({&evaluator}, start, parameters);
  twin::IdentificationResult result = twin::identify_gradient(problem, {});
  INFO(result.stop_reason);
  twin::estimate_uncertainty(problem, result);
  for (const twin::ParameterEstimate& e : result.estimates) {
    const double truth = twin::get_parameter(lab.truth, e.parameter);
    INFO(twin::parameter_name(e.parameter) << " = " << e.value << " [" << e.lower95 << ", " << e.upper95
                                           << "], truth " << truth << "; " << result.simulations
                                           << " simulations, noise " << result.noise_sigma_m << " m");
    CHECK(std::abs(e.value - truth) <= tolerance * std::abs(truth));
    CHECK(e.lower95 <= truth);
    CHECK(truth <= e.upper95);
  }
  CHECK(result.noise_sigma_m < 0.5e-3);  // down to the scanner noise (0.3 mm per axis)
}

TEST_CASE("a roll set in the lab's sheet is identified from trials, starting flat", "[effects][identification]") {
  twin::ModelEffects effects;
  effects.rest_curvature_uu_1_m = 3.0;
  check_recovered(lab_trial_with(effects), {MaterialParameter::kRestCurvatureUU}, 0.05);
}

TEST_CASE("bending stiffening in the lab's sheet is identified from trials, starting without",
          "[effects][identification]") {
  twin::ModelEffects effects;
  effects.bending_stiffening_m2 = 0.01;
  check_recovered(lab_trial_with(effects), {MaterialParameter::kBendingStiffening}, 0.1);
}

}  // namespace
