// A refit search's result as bytes (twin/diagnosis/refit_search_codec.h): what a rank sends is
// what the receiving rank decodes, bit for bit, with the material rebuilt from its problem.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

#include "sim_hw/scanner_lab.h"
#include "tests/support/uniform_lab_config.h"
#include "twin/diagnosis/effect_library.h"
#include "twin/diagnosis/refit_search_codec.h"

namespace {

namespace dx = twin::diagnosis;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("a refit search's result crosses ranks bit for bit, and bad bytes are refused", "[diagnosis][refit]") {
  const sim_hw::LabTrial lab = sim_hw::make_lab_trial(testing_support::uniform_lab_config(3, 100));
  twin::TrialEvaluator evaluator(lab.trial, 100, lab.truth);
  const dx::CandidateEffect& ortho = dx::find_effect("orthotropic_stiffness");
  const twin::IdentificationProblem problem({&evaluator}, lab.truth, ortho.refit_parameters);

  twin::IdentificationResult sent;
  sent.method = "ours: equilibrium tangents + Levenberg-Marquardt";
  sent.objective_name = "mean squared marker residual per coordinate (mm^2)";
  sent.stop_reason = "relative step below 1e-6; bending_v_Nm at the edge of its search range: restart from there";
  sent.start_coordinates = problem.coordinates_of(lab.truth);
  sent.coordinates = sent.start_coordinates;
  sent.coordinates(0) += 0.1 + 0.2;  // a value with no short decimal form
  sent.coordinates(sent.coordinates.size() - 1) -= 1.0 / 3.0;
  sent.objective = 0.09000000000000001;
  sent.evaluations = 37;
  sent.simulations = 41;
  sent.seconds = 12.5;
  sent.noise_sigma_m = std::numeric_limits<double>::quiet_NaN();
  sent.at_search_edge.assign(static_cast<std::size_t>(sent.coordinates.size()), 0);
  sent.at_search_edge.back() = -1;
  sent.material = problem.material_at(sent.coordinates);

  const std::string bytes = dx::encode_refit_search(sent, 2);
  const dx::DecodedRefitSearch got = dx::decode_refit_search(bytes, problem);
  CHECK(got.rank == 2);
  const twin::IdentificationResult& r = got.result;
  CHECK(r.method == sent.method);
  CHECK(r.objective_name == sent.objective_name);
  CHECK(r.stop_reason == sent.stop_reason);
  REQUIRE(r.coordinates.size() == sent.coordinates.size());
  for (Eigen::Index j = 0; j < r.coordinates.size(); ++j) {
    CHECK(same_bits(r.coordinates(j), sent.coordinates(j)));
    CHECK(same_bits(r.start_coordinates(j), sent.start_coordinates(j)));
  }
  CHECK(same_bits(r.objective, sent.objective));
  CHECK(r.evaluations == 37);
  CHECK(r.simulations == 41);
  CHECK(r.seconds == 12.5);
  CHECK(std::isnan(r.noise_sigma_m));
  CHECK(r.at_search_edge == sent.at_search_edge);
  CHECK(same_bits(r.material.bending_rigidity_v_Nm, sent.material.bending_rigidity_v_Nm));
  CHECK(same_bits(r.material.tensile_stiffness_u_N_m, sent.material.tensile_stiffness_u_N_m));

  // Truncated, padded, or for another parameter list: errors, never a result.
  CHECK_THROWS_WITH(dx::decode_refit_search(bytes.substr(0, bytes.size() - 1), problem), Catch::Contains("ends early"));
  CHECK_THROWS_WITH(dx::decode_refit_search(bytes + "x", problem), Catch::Contains("bytes left"));
  const twin::IdentificationProblem base_only({&evaluator}, lab.truth, twin::diagnosis::base_parameters());
  CHECK_THROWS_WITH(dx::decode_refit_search(bytes, base_only), Catch::Contains("coordinates for 3 parameters"));
  // Intervals come after the searches: a result with them is not a search's.
  twin::IdentificationResult finished = sent;
  finished.estimates.resize(1);
  CHECK_THROWS_AS(dx::encode_refit_search(finished, 0), std::invalid_argument);
}
