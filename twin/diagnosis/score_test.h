#pragma once
// The score (Lagrange multiplier) test of a candidate effect at the base fit: does the
// residual have a component along the directions the effect's parameters move the markers,
// beyond what the base parameters already explain? No refit is needed: one evaluation with the
// Jacobian of base + effect parameters.
//
// With residuals r (n), the base Jacobian Jb (n x kb) and the effect's columns Je (n x ke), and
// P_A the orthogonal projection onto the column span of A:
//   statistic = (|P_[Jb Je] r|^2 - |P_Jb r|^2) / sigma^2
// At the exact base optimum Jb^T r = 0 and this is the textbook r^T J (J^T J)^-1 J^T r / sigma^2;
// subtracting the base part keeps it right when the base fit stopped a little short. Under the
// null (the effect absent, Gaussian noise of sigma per coordinate) it is chi-square with dof =
// the rank the effect adds (columns without sensitivity add none and are reported as such).
// explained_fraction = the same numerator / |r|^2: how much of the residual the effect's span
// can take.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "twin/diagnosis/effect_library.h"
#include "twin/trials/trial_evaluator.h"

namespace twin::diagnosis {

struct ScoreStatistic {
  double statistic = 0.0;           // chi-square under the null
  int dof = 0;                      // rank added by the effect's columns
  double p_value = 1.0;             // upper tail of chi-square(dof) at statistic
  double explained_fraction = 0.0;  // of |r|^2
  // The Gauss-Newton step of all the test's parameters from the base fit, in search
  // coordinates: minimises |r + J step| (least norm where columns add no rank). A refit starts
  // there too (refit.h): it is the one-step estimate of the effect.
  Eigen::VectorXd step;
  // Of the twin's own discretisation error (the residual's change to a finer twin,
  // discretisation_check.h), the part the effect's span takes beyond the base span: what a refit
  // with this effect could remove without any effect in the data (m^2, summed); negative when
  // not computed.
  double absorbable_m2 = -1.0;
};

// The statistic above. Columns are scaled to unit norm before the rank-revealing QR, so
// parameters of very different units are treated alike; a column whose norm is below
// 1e-9 of the largest, or that is dependent on the others, adds no rank.
// With `discretisation_change_m` (same length as the residuals), absorbable_m2 too.
ScoreStatistic score_statistic(const Eigen::VectorXd& residuals_m, const Eigen::MatrixXd& base_jacobian,
                               const Eigen::MatrixXd& effect_jacobian, double sigma_m,
                               const Eigen::VectorXd* discretisation_change_m = nullptr);

// Where a profiled candidate's statistic was taken: its profiled parameter's value, and how many
// values were tried (the Bonferroni factor of its p-value).
struct ScoreProfilePoint {
  MaterialParameter parameter;
  double value = 0.0;
  int values_tried = 0;
};

struct CandidateScore {
  std::string effect;
  std::string skipped;      // why the candidate was not tested ("" when it was)
  ScoreStatistic score;     // for a profiled candidate: at the value with the largest statistic
  std::optional<ScoreProfilePoint> profile;  // that value (CandidateEffect::score_profile), else none
};

// Evaluates the training trials once per candidate at `base_fit` (the effect absent) with the
// Jacobian of the candidate's score parameters, and returns the statistics in the candidates'
// order; a profiled candidate once per profile value (effect_library.h). Warm starts are
// dropped between candidates (their parameter lists differ).
// With `discretisation_change_m` (the discretisation error of the training trials at base_fit
// their residual holds: DiscretisationCheck::error_pattern_m scaled by pattern_in_residual),
// each score's absorbable_m2 too.
std::vector<CandidateScore> score_candidates(const std::vector<CandidateEffect>& candidates,
                                             const std::vector<TrialEvaluator*>& training, const Material& base_fit,
                                             double sigma_m, const Eigen::VectorXd* discretisation_change_m = nullptr);

}  // namespace twin::diagnosis
