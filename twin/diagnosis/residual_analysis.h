#pragma once
// Is the residual field of a fit (residual_field.h) more than measurement noise, where, and what
// does it look like? (issue 6, step 1)
//
// Significance: with independent Gaussian noise of sigma per coordinate, the sum of squared
// residuals / sigma^2 over a set of markers is chi-square with 3 * (markers) dof (the overall
// test charges the fitted parameters too). Tested: overall, per stage, and per region per stage
// (the sheet's bounding box in material coordinates cut into rows x cols regions). A test is
// significant when its upper-tail p-value is below alpha / (number of tests made): Bonferroni,
// so that pure noise flags nothing with probability >= 1 - alpha over the whole analysis.
//
// Structure (sentences plus the numbers behind them):
//  - warp/weft: of the normal-component residual's variance (per-stage means removed), the
//    fraction explained by a cubic in u alone and by a cubic in v alone (per-stage
//    coefficients), each with the p-value of its explained sum of squares / sigma^2 as chi-square
//    (known sigma) with 3 dof per stage; "varies along u
//    (weft)" when u explains clearly more than v and is significant, and conversely.
//  - Pearson correlation of |residual| with distance from the clamps and predicted curvature
//    (over samples), and of the stage's RMS residual with stage load and stage age (over
//    stages: one value per stage, so stages count as the independent units; age only where
//    known), with a two-sided p-value (Fisher z); notable when p < alpha and |r| >= 0.2.

#include <array>
#include <string>
#include <vector>

#include "twin/diagnosis/chi_square.h"
#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

struct ChiSquareTest {
  double chi_square = 0.0;   // sum r^2 / sigma^2
  double dof = 0.0;
  double p_value = 1.0;
  bool significant = false;  // p_value < the Bonferroni level
  int samples = 0;           // markers in the test
  double rms_m = 0.0;        // per-coordinate RMS of the residual (m)
  bool tested() const { return samples > 0; }
};

struct AnalysisOptions {
  double alpha = 0.05;       // family-wise error rate of the whole analysis
  int region_rows = 3;       // regions along v
  int region_cols = 3;       // regions along u
  int min_region_samples = 3;  // smaller regions are not tested
};

struct RegionResult {
  int row = 0, col = 0;       // row along v (0 at v min), col along u (0 at u min)
  Vec2 min_uv_m = Vec2::Zero(), max_uv_m = Vec2::Zero();  // its box in its trial's material coordinates
  ChiSquareTest test;
};

struct StageResult {
  ChiSquareTest test;
  std::vector<RegionResult> regions;  // region_rows * region_cols, row-major
};

struct Correlation {
  std::string quantity;      // "clamp distance", "curvature", "stage load", "stage age"
  double r = 0.0;            // Pearson correlation with |residual| (or the stage RMS)
  double p_value = 1.0;
  int samples = 0;           // pairs used; 0 when not computable (constant or unknown quantity)
  bool notable = false;
};

struct DirectionStructure {
  double explained_by_u = 0.0;  // fraction of normal-residual variance, cubic in u per stage
  double explained_by_v = 0.0;
  double p_u = 1.0, p_v = 1.0;  // chi-square p-values of the explained sums of squares
  std::string direction;        // "u", "v" or "" (neither dominates)
};

struct ResidualAnalysis {
  double sigma_m = 0.0;
  double bonferroni_level = 0.0;  // alpha / tests
  int tests = 0;
  ChiSquareTest overall;
  std::vector<StageResult> stages;  // parallel to ResidualField::stages
  DirectionStructure direction;
  std::vector<Correlation> correlations;
  std::vector<std::string> sentences;  // plain-language findings, most important first

  bool any_significant() const;
  int significant_stage_count() const;
  int significant_region_count() const;
};

// Throws std::invalid_argument when sigma_m is not positive and finite or the field is empty.
ResidualAnalysis analyse_residuals(const ResidualField& field, double sigma_m,
                                   const AnalysisOptions& options = {});

}  // namespace twin::diagnosis
