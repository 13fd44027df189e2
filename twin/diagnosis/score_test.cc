#include "twin/diagnosis/score_test.h"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

#include "twin/diagnosis/chi_square.h"
#include "twin/trials/identification.h"
#include "twin/model/material_parameters.h"

namespace twin::diagnosis {
namespace {

struct Projection {
  double square = 0.0;   // |P_A r|^2
  double other_square = 0.0;  // |P_A o|^2 of the optional second vector o
  int rank = 0;
  Eigen::VectorXd step;  // minimises |r + A step| (zero for columns that add no rank)
};

// With A's columns scaled to unit norm first (parameters of very different units alike). With
// `other`, its projection too, from the same factorisation.
Projection project(const Eigen::MatrixXd& a, const Eigen::VectorXd& r, const Eigen::VectorXd* other = nullptr) {
  Projection p;
  p.step = Eigen::VectorXd::Zero(a.cols());
  if (a.cols() == 0) return p;
  const Eigen::VectorXd norms = a.colwise().norm().transpose();
  const double largest = norms.maxCoeff();
  if (!(largest > 0.0)) return p;
  Eigen::MatrixXd scaled(a.rows(), a.cols());
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(a.cols());
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    if (norms(j) > 1e-9 * largest) inverse(j) = 1.0 / norms(j);
    scaled.col(j) = a.col(j) * inverse(j);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  qr.setThreshold(1e-8);
  p.rank = static_cast<int>(qr.rank());
  const Eigen::VectorXd qtr = qr.householderQ().transpose() * r;
  p.square = qtr.head(p.rank).squaredNorm();
  if (other) p.other_square = (qr.householderQ().transpose() * *other).head(p.rank).squaredNorm();
  // Basic solution over the independent columns, the others zero.
  const Eigen::VectorXd z = qr.matrixR().topLeftCorner(p.rank, p.rank).triangularView<Eigen::Upper>().solve(qtr.head(p.rank));
  Eigen::VectorXd permuted = Eigen::VectorXd::Zero(a.cols());
  permuted.head(p.rank) = z;
  p.step = -(inverse.asDiagonal() * (qr.colsPermutation() * permuted));
  return p;
}

}  // namespace

ScoreStatistic score_statistic(const Eigen::VectorXd& residuals_m, const Eigen::MatrixXd& base_jacobian,
                               const Eigen::MatrixXd& effect_jacobian, double sigma_m,
                               const Eigen::VectorXd* discretisation_change_m) {
  Eigen::MatrixXd joint(residuals_m.size(), base_jacobian.cols() + effect_jacobian.cols());
  joint << base_jacobian, effect_jacobian;
  const Eigen::VectorXd* change =
      discretisation_change_m && discretisation_change_m->size() == residuals_m.size() ? discretisation_change_m : nullptr;
  const Projection base = project(base_jacobian, residuals_m, change);
  const Projection both = project(joint, residuals_m, change);
  ScoreStatistic s;
  s.step = both.step;
  s.dof = both.rank - base.rank;
  if (change) s.absorbable_m2 = std::max(0.0, both.other_square - base.other_square);
  if (s.dof <= 0) return s;
  const double gain = std::max(0.0, both.square - base.square);
  s.statistic = gain / (sigma_m * sigma_m);
  s.p_value = chi_square_upper_tail(s.statistic, s.dof);
  const double total = residuals_m.squaredNorm();
  s.explained_fraction = total > 0.0 ? gain / total : 0.0;
  return s;
}

std::vector<CandidateScore> score_candidates(const std::vector<CandidateEffect>& candidates,
                                             const std::vector<TrialEvaluator*>& training, const Material& base_fit,
                                             double sigma_m, const Eigen::VectorXd* discretisation_change_m) {
  std::vector<const Trial*> trials;
  for (TrialEvaluator* t : training) trials.push_back(&t->trial());
  std::vector<CandidateScore> scores;
  for (const CandidateEffect& effect : candidates) {
    CandidateScore c;
    c.effect = effect.name;
    c.skipped = applicability(effect, trials);
    if (c.skipped.empty()) {
      for (TrialEvaluator* t : training) t->clear_warm_starts();
      // The profile's values (or the null material's own, once). The effect is absent at each,
      // so the equilibria are the same and the warm starts carry over.
      std::vector<std::optional<double>> values{std::nullopt};
      if (effect.score_profile) values.assign(effect.score_profile->values.begin(), effect.score_profile->values.end());
      bool tested = false;
      for (const std::optional<double>& value : values) {
        Material at = null_material(effect, base_fit);
        if (value) set_parameter(at, effect.score_profile->parameter, *value);
        IdentificationProblem problem(training, at, effect.score_parameters);
        const IdentificationProblem::Evaluation e =
            problem.evaluate(problem.coordinates_of(at), Derivatives::kJacobian, 2.0);
        if (!e.usable()) {
          c.skipped = "the simulation at the base fit failed: " + e.failure;
          break;
        }
        const int kb = static_cast<int>(base_parameters().size());
        const ScoreStatistic s = score_statistic(
            e.residuals_m, e.coordinate_jacobian.leftCols(kb),
            e.coordinate_jacobian.rightCols(e.coordinate_jacobian.cols() - kb), sigma_m, discretisation_change_m);
        if (s.dof > 0 && (!tested || s.statistic > c.score.statistic)) {
          c.score = s;
          if (value) c.profile = ScoreProfilePoint{effect.score_profile->parameter, *value, static_cast<int>(values.size())};
          tested = true;
        }
      }
      if (c.skipped.empty() && !tested) c.skipped = "the markers do not respond to its parameters";
      // Bonferroni over the values tried: the largest of several statistics is not chi-square.
      if (tested && values.size() > 1) c.score.p_value = std::min(1.0, c.score.p_value * values.size());
    }
    scores.push_back(c);
  }
  for (TrialEvaluator* t : training) t->clear_warm_starts();
  return scores;
}

}  // namespace twin::diagnosis
