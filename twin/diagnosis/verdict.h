#pragma once
// The decision of `twin diagnose`, with its thresholds:
//
// 1. Is there anything to explain? The base fit's residual is compared with the noise floor on
//    the training and on the held-out trials: chi-square S / sigma^2 with n (held-out) or
//    n - 3 (training) degrees of freedom. It is significant when p < kResidualAlpha AND its RMS
//    per coordinate exceeds sigma by more than kNoiseTolerance (an estimated sigma is itself
//    uncertain by a few per cent, and a few thousand residuals make the chi-square test see
//    that alone). Neither set significant -> "none" (no missing effect supported).
// 2. Which candidate? A candidate qualifies when its score test is significant at
//    kScoreAlpha / (candidates tested) (Bonferroni) and its refit lowers the BIC below the
//    base fit's and lowers the held-out mean correspondence error, and its own 95 % intervals
//    put some strength of the effect away from "absent" (null_material(); a relaxation time or
//    a grip width does not count: it means nothing while the effect is absent; a candidate
//    whose refit gives no estimates is not checked). Of the qualifying ones the
//    one with the lowest held-out sum of squares wins. (diagnose.cc refits only candidates
//    significant in the score test; with none, the closest is the one explaining the most.)
// 3. Does it explain the discrepancy? The winner must leave the mean marker error within
//    kFloorRatio of the noise floor (sigma sqrt(8/pi), the mean error noise alone leaves: the
//    acceptance the issue sets for a named effect) on the training AND the held-out trials.
//    The test is on the mean, not the RMS: a few markers on a neighbouring equilibrium (a
//    corner folded the other way in one trial's simulation) dominate an RMS while the rest of
//    the sheet fits. It must also leave at most kMaxSignificantStageFraction of the training
//    stages significant (the per-stage chi-square of residual_analysis.h, Bonferroni over all
//    its tests): an effect that explains the discrepancy explains it in most stages, while a
//    wrong candidate can pull the mean down by absorbing part of an effect outside the library
//    (seen: the creases of a folded ply "explained" by orthotropy down to 1.3x the floor, with
//    9 of 10 training stages still significant). And it must take at least kMinGapExplained of
//    the base fit's gap, the mean marker error above the noise floor, on each set (training,
//    held-out) whose base residual is significant: a base fit already near 1.5x the floor passes
//    the floor check whatever is added, and a candidate that moves the mean error by a few
//    micrometres there explains nothing (seen: the creases of a folded ply, base at 1.2x the
//    floor, "explained" by rest curvature, held-out 0.605 -> 0.605 mm, 1 % of the gap). Then
//    "effect"; otherwise, or when no candidate qualifies, "unexplained", naming the closest
//    candidate and how much of the residual it took.
//
// The twin's own error. The twin at its resolution misses the continuum, and the part of that
// error the base fit's residual holds, d per coordinate, is measured (discretisation_check.h: the
// base fit's markers on twice the triangles give the error's pattern, and the residual's
// least-squares coefficient along it how much of it is there; none when not measured). Noise and
// discretisation together explain a residual RMS of b = sqrt(sigma^2 + d^2). Then:
//  - a candidate qualifies only when its refit removes more than it could take of the twin's own
//    error (an effect's parameters can bend the twin toward its finer self): the training sum
//    of squares falls by more than (2 b)^2, b^2 the part of the residual's change to a finer twin
//    in the effect's span beyond the base span (CandidateScore absorbable_m2: were effect and
//    discretisation aligned, the refit would remove (a + b)^2, so more than (2 b)^2 means the
//    effect's own part a exceeds b); without that projection, by more than d^2 per residual;
//  - step 3 measures "explains" against b: the floor is b sqrt(8/pi) and the gap is above it;
//  - no effect explaining it (and d measured): a base fit beyond kModelFormFactor b on the
//    training trials is
//    "model_form" (the model is wrong in a way no candidate explains; diagnose.cc says where),
//    one within kNoiseTolerance b on both sets is "none" (what remains is what the noise and the
//    twin's resolution leave: no missing effect is supported at this resolution), and anything
//    between is "unexplained".
// Not measured, all of this is the rules above: "model_form" needs the discretisation measured
// (a large residual may be the resolution alone), the "none" of a resolution needs d > 0.

#include <optional>
#include <string>
#include <vector>

#include "twin/diagnosis/refit.h"
#include "twin/diagnosis/score_test.h"

namespace twin::diagnosis {

inline constexpr double kResidualAlpha = 1e-3;
inline constexpr double kNoiseTolerance = 1.05;     // residual RMS / sigma above which it is "more than noise"
inline constexpr double kScoreAlpha = 1e-3;         // family-wise, over the candidates tested
inline constexpr double kFloorRatio = 1.5;  // mean marker error / noise floor left by an accepted effect
inline constexpr double kMaxSignificantStageFraction = 0.5;  // training stages an accepted effect may leave significant
inline constexpr double kMinGapExplained = 0.25;  // share of the base's mean error above the floor an accepted effect removes
// A training RMS beyond this multiple of sqrt(sigma^2 + d^2) (noise sigma, discretisation d) is a
// model-form misfit: twice is far beyond the sampling spread of an RMS over hundreds of residuals.
inline constexpr double kModelFormFactor = 2.0;

struct ResidualTest {
  double chi_square = 0.0, dof = 0.0, p_value = 1.0, rms_ratio = 0.0;  // rms_ratio: RMS / sigma
  bool significant = false;
};
// sigma_relative_error: the relative standard error of an estimated sigma (0 when given): the
// RMS must then exceed kNoiseTolerance by two of them more, so that an estimate a little low by
// chance does not make noise "significant".
ResidualTest residual_test(const SetScore& set, int fitted_parameters, double sigma_m,
                           double sigma_relative_error = 0.0);

struct Verdict {
  std::string verdict;                 // "effect" | "none" | "unexplained" | "model_form"
  std::optional<std::string> effect;   // named effect ("effect" only)
  std::optional<std::string> closest;  // best candidate when "unexplained" or "model_form"
  double budget_m = 0.0;               // sqrt(sigma^2 + d^2): what noise and discretisation explain
  std::string summary;                 // one line
  std::vector<std::string> reasons;    // the evidence, one sentence each
  const Refit* chosen = nullptr;       // refit of the named effect (or of the closest one)
};

// discretisation_m: d above (none: not measured).
Verdict decide(const SetScore& base_train, const SetScore& base_test, double base_bic,
               const std::vector<CandidateScore>& scores, const std::vector<Refit>& refits, double sigma_m,
               double sigma_relative_error = 0.0, std::optional<double> discretisation_m = std::nullopt);

}  // namespace twin::diagnosis
