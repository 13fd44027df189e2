// Stage weights of the robust refit (twin/diagnosis/stage_weights.h): no simulation.
#include <catch2/catch.hpp>

#include <cmath>

#include "twin/diagnosis/stage_weights.h"

namespace {

namespace dx = twin::diagnosis;

// A trial fit whose stages have the given RMS residuals per coordinate (m): each stage has
// four observations (12 residuals), one per quarter, every coordinate at +-rms.
twin::TrialFit fit_with_stage_rms(const std::vector<double>& rms) {
  twin::TrialFit fit;
  std::vector<double> r;
  for (std::size_t s = 0; s < rms.size(); ++s) {
    fit.stages.push_back({});
    fit.stages.back().id = std::to_string(s + 1);
    for (int quarter = 0; quarter < 4; ++quarter) {
      for (int k = 0; k < 3; ++k) {
        r.push_back((k % 2 == 0 ? 1.0 : -1.0) * rms[s]);
        fit.residual_blocks.push_back(4 * static_cast<int>(s) + quarter);
      }
    }
  }
  fit.residuals_m = Eigen::Map<const twin::VecX>(r.data(), static_cast<Eigen::Index>(r.size()));
  fit.residual_count = static_cast<int>(r.size());
  return fit;
}

}  // namespace

TEST_CASE("a stage far above the median stage misfit is down-weighted to the ratio's level", "[diagnosis][robust]") {
  twin::IdentificationProblem::Evaluation e;
  e.fits.push_back(fit_with_stage_rms({3e-4, 3.2e-4, 6e-3}));  // the third: 20x the median
  e.fits.push_back(fit_with_stage_rms({2.9e-4, 5e-4, 3.1e-4}));  // 1.6x: an ordinary stage
  const dx::StageWeights w = dx::outlier_stage_weights(e, {"train_1", "train_2"});
  CHECK(w.median_rms_m == Approx(3.2e-4));  // the upper median of the six
  REQUIRE(w.outliers.size() == 1);
  CHECK(w.outliers[0].trial == "train_1");
  CHECK(w.outliers[0].stage == "3");
  CHECK(w.outliers[0].ratio == Approx(6e-3 / 3.2e-4));
  // Its weighted misfit is that of a stage at kOutlierStageRatio times the median.
  const double weighted_rms = std::sqrt(w.outliers[0].weight) * 6e-3;
  CHECK(weighted_rms == Approx(dx::kOutlierStageRatio * 3.2e-4));
  REQUIRE(w.weights.size() == 2);
  CHECK(w.weights[0] == std::vector<double>{1.0, 1.0, w.outliers[0].weight});
  CHECK(w.weights[1] == std::vector<double>{1.0, 1.0, 1.0});
}

TEST_CASE("stages at a similar misfit, or too few stages, are left alone", "[diagnosis][robust]") {
  twin::IdentificationProblem::Evaluation e;
  e.fits.push_back(fit_with_stage_rms({3e-4, 8e-4, 5e-4, 2.9e-4}));  // at most 2.7x the median
  CHECK(dx::outlier_stage_weights(e, {"a"}).outliers.empty());
  twin::IdentificationProblem::Evaluation two;
  two.fits.push_back(fit_with_stage_rms({3e-4, 3e-2}));  // no median to speak of
  const dx::StageWeights w = dx::outlier_stage_weights(two, {"a"});
  CHECK(w.outliers.empty());
  CHECK(w.weights[0] == std::vector<double>{1.0, 1.0});
}
