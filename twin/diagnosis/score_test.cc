#include "twin/diagnosis/score_test.h"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

#include "twin/diagnosis/chi_square.h"
#include "twin/identification.h"

namespace twin::diagnosis {
namespace {

// |P_A r|^2 and the rank of A, with A's columns scaled to unit norm first.
std::pair<double, int> projected_square(const Eigen::MatrixXd& a, const Eigen::VectorXd& r) {
  if (a.cols() == 0) return {0.0, 0};
  const Eigen::VectorXd norms = a.colwise().norm().transpose();
  const double largest = norms.maxCoeff();
  if (!(largest > 0.0)) return {0.0, 0};
  Eigen::MatrixXd scaled(a.rows(), a.cols());
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    scaled.col(j) = norms(j) > 1e-9 * largest ? Eigen::VectorXd(a.col(j) / norms(j)) : Eigen::VectorXd::Zero(a.rows());
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  qr.setThreshold(1e-8);
  const int rank = static_cast<int>(qr.rank());
  const Eigen::VectorXd qtr = qr.householderQ().transpose() * r;
  return {qtr.head(rank).squaredNorm(), rank};
}

}  // namespace

ScoreStatistic score_statistic(const Eigen::VectorXd& residuals_m, const Eigen::MatrixXd& base_jacobian,
                               const Eigen::MatrixXd& effect_jacobian, double sigma_m) {
  Eigen::MatrixXd joint(residuals_m.size(), base_jacobian.cols() + effect_jacobian.cols());
  joint << base_jacobian, effect_jacobian;
  const auto [base_square, base_rank] = projected_square(base_jacobian, residuals_m);
  const auto [joint_square, joint_rank] = projected_square(joint, residuals_m);
  ScoreStatistic s;
  s.dof = joint_rank - base_rank;
  if (s.dof <= 0) return s;
  const double gain = std::max(0.0, joint_square - base_square);
  s.statistic = gain / (sigma_m * sigma_m);
  s.p_value = chi_square_upper_tail(s.statistic, s.dof);
  const double total = residuals_m.squaredNorm();
  s.explained_fraction = total > 0.0 ? gain / total : 0.0;
  return s;
}

std::vector<CandidateScore> score_candidates(const std::vector<CandidateEffect>& candidates,
                                             const std::vector<TrialEvaluator*>& training, const Material& base_fit,
                                             double sigma_m) {
  std::vector<const Trial*> trials;
  for (TrialEvaluator* t : training) trials.push_back(&t->trial());
  std::vector<CandidateScore> scores;
  for (const CandidateEffect& effect : candidates) {
    CandidateScore c;
    c.effect = effect.name;
    c.skipped = applicability(effect, trials);
    if (c.skipped.empty()) {
      for (TrialEvaluator* t : training) t->clear_warm_starts();
      const Material at = null_material(effect, base_fit);
      IdentificationProblem problem(training, at, effect.score_parameters);
      const IdentificationProblem::Evaluation e =
          problem.evaluate(problem.coordinates_of(at), Derivatives::kJacobian, 2.0);
      if (!e.usable()) {
        c.skipped = "the simulation at the base fit failed: " + e.failure;
      } else {
        const int kb = static_cast<int>(base_parameters().size());
        c.score = score_statistic(e.residuals_m, e.coordinate_jacobian.leftCols(kb),
                                  e.coordinate_jacobian.rightCols(e.coordinate_jacobian.cols() - kb), sigma_m);
        if (c.score.dof == 0) c.skipped = "the markers do not respond to its parameters";
      }
    }
    scores.push_back(c);
  }
  for (TrialEvaluator* t : training) t->clear_warm_starts();
  return scores;
}

}  // namespace twin::diagnosis
