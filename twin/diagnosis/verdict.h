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
  std::string verdict;                 // "effect" | "none" | "unexplained"
  std::optional<std::string> effect;   // named effect ("effect" only)
  std::optional<std::string> closest;  // best candidate when "unexplained"
  std::string summary;                 // one line
  std::vector<std::string> reasons;    // the evidence, one sentence each
  const Refit* chosen = nullptr;       // refit of the named effect (or of the closest one)
};

Verdict decide(const SetScore& base_train, const SetScore& base_test, double base_bic,
               const std::vector<CandidateScore>& scores, const std::vector<Refit>& refits, double sigma_m,
               double sigma_relative_error = 0.0);

}  // namespace twin::diagnosis
