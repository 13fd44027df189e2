#include "twin/trials/identification.h"

#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace twin {

IdentificationProblem::IdentificationProblem(std::vector<TrialEvaluator*> training, Material base,
                                             std::vector<MaterialParameter> parameters)
    : training_(std::move(training)), base_(std::move(base)), parameters_(std::move(parameters)) {
  if (training_.empty()) throw std::invalid_argument("identification needs at least one training trial");
  if (parameters_.empty()) throw std::invalid_argument("identification needs at least one parameter to vary");
}

Material IdentificationProblem::material_at(const VecX& coordinates) const {
  Material m = base_;
  for (std::size_t j = 0; j < parameters_.size(); ++j) set_parameter(m, parameters_[j], from_search_coordinate(parameters_[j], coordinates(j)));
  return m;
}

VecX IdentificationProblem::coordinates_of(const Material& material) const {
  VecX v(static_cast<Eigen::Index>(parameters_.size()));
  for (std::size_t j = 0; j < parameters_.size(); ++j) v(j) = to_search_coordinate(parameters_[j], get_parameter(material, parameters_[j]));
  return v;
}

void IdentificationProblem::set_stage_weights(std::vector<std::vector<double>> weights) {
  if (!weights.empty() && weights.size() != training_.size()) {
    throw std::invalid_argument(fmt::format("stage weights: expected one list per training trial ({}), got {}",
                                            training_.size(), weights.size()));
  }
  for (const std::vector<double>& trial : weights) {
    for (double w : trial) {
      if (!(w > 0.0 && w <= 1.0)) throw std::invalid_argument(fmt::format("stage weights: expected (0, 1], got {}", w));
    }
  }
  stage_weights_ = std::move(weights);
}

double IdentificationProblem::stage_weight(std::size_t trial, int stage) const {
  if (stage_weights_.empty()) return 1.0;
  const std::vector<double>& w = stage_weights_[trial];
  return stage >= 0 && static_cast<std::size_t>(stage) < w.size() ? w[stage] : 1.0;
}

IdentificationProblem::Evaluation IdentificationProblem::evaluate(const VecX& coordinates, Derivatives derivatives,
                                                                  double max_weight, bool fresh) {
  const auto start = std::chrono::steady_clock::now();
  const bool weighted = !stage_weights_.empty();
  if (weighted && derivatives == Derivatives::kGradient) {
    throw std::logic_error("identification with stage weights needs the Jacobian (Levenberg-Marquardt), not the adjoint gradient");
  }
  Evaluation e;
  const Material material = material_at(coordinates);
  double weight_sum = 0.0;  // sum of the residuals' weights (their count when unweighted)
  double sum_squares = 0.0;
  for (TrialEvaluator* trial : training_) {
    e.fits.push_back(trial->evaluate(material, parameters_, derivatives, fresh));
    ++simulations_;
    const TrialFit& fit = e.fits.back();
    if (!fit.usable()) {
      e.failure = fmt::format("{}: {}", trial->trial().directory, fit.failure);
      break;
    }
    e.nearest_score_m += fit.nearest_score_m(max_weight);
    e.residual_count += fit.residual_count;
    if (!weighted) {
      sum_squares += fit.sum_squares_m2;
      weight_sum += fit.residual_count;
      continue;
    }
    const std::size_t t = e.fits.size() - 1;
    for (Eigen::Index i = 0; i < fit.residuals_m.size(); ++i) {
      const double w = stage_weight(t, fit.residual_blocks[i] / 4);  // block = stage * 4 + quarter
      sum_squares += w * fit.residuals_m(i) * fit.residuals_m(i);
      weight_sum += w;
    }
  }
  if (e.usable() && e.residual_count > 0) {
    e.mean_square_m2 = sum_squares / weight_sum;
    if (derivatives != Derivatives::kNone) {
      e.coordinate_gradient = VecX::Zero(coordinates.size());
      for (const TrialFit& fit : e.fits) e.coordinate_gradient += fit.coordinate_gradient / e.residual_count;
    }
    if (derivatives == Derivatives::kJacobian) {
      e.coordinate_jacobian.resize(e.residual_count, coordinates.size());
      e.residuals_m.resize(e.residual_count);
      e.residual_blocks.clear();
      Eigen::Index row = 0;
      for (std::size_t t = 0; t < e.fits.size(); ++t) {
        const TrialFit& fit = e.fits[t];
        e.coordinate_jacobian.middleRows(row, fit.residual_count) = fit.coordinate_jacobian;
        e.residuals_m.segment(row, fit.residual_count) = fit.residuals_m;
        for (int i = 0; i < fit.residual_count; ++i) {
          const int b = fit.residual_blocks[i];
          e.residual_blocks.push_back(1000 * static_cast<int>(t) + b);
          if (!weighted) continue;
          const double root = std::sqrt(stage_weight(t, b / 4));
          e.residuals_m(row + i) *= root;
          e.coordinate_jacobian.row(row + i) *= root;
        }
        row += fit.residual_count;
      }
      if (weighted) e.coordinate_gradient = 2.0 * e.coordinate_jacobian.transpose() * e.residuals_m / weight_sum;
    }
  } else if (e.usable()) {
    e.failure = "no observation was scored (every marker hidden?)";
  }
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (on_evaluation) on_evaluation(coordinates, e);
  return e;
}

void IdentificationProblem::forget_warm_starts() {
  for (TrialEvaluator* t : training_) t->clear_warm_starts();
}

void estimate_uncertainty(IdentificationProblem& problem, IdentificationResult& result, IntervalKind kind,
                          const VecX* discretisation_error_m) {
  const IdentificationProblem::Evaluation e =
      problem.evaluate(result.coordinates, Derivatives::kJacobian, /*max_weight=*/0.5);
  ++result.simulations;
  result.estimates.clear();
  const auto P = result.coordinates.size();
  for (Eigen::Index j = 0; j < P; ++j) {
    ParameterEstimate est;
    est.parameter = problem.parameters()[j];
    est.value = from_search_coordinate(est.parameter, result.coordinates(j));
    est.lower95 = 0.0;
    est.upper95 = std::numeric_limits<double>::infinity();
    result.estimates.push_back(est);
  }
  if (!e.usable()) return;  // every parameter stays "not determined"
  const double dof = std::max(1.0, static_cast<double>(e.residual_count - P));
  const double sigma2 = e.residuals_m.squaredNorm() / dof;
  result.noise_sigma_m = std::sqrt(sigma2);
  const Eigen::MatrixXd fisher = e.coordinate_jacobian.transpose() * e.coordinate_jacobian;
  // A parameter with no effect on the markers makes J^T J singular: its variance is infinite.
  // The pseudo-inverse by eigen-decomposition keeps the determined ones finite.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(fisher);
  const double largest = eig.eigenvalues().cwiseAbs().maxCoeff();
  Eigen::MatrixXd inverse = Eigen::MatrixXd::Zero(P, P);  // pseudo-inverse of J^T J
  VecX unbounded = VecX::Zero(P);
  for (Eigen::Index k = 0; k < P; ++k) {
    const double lambda = eig.eigenvalues()(k);
    const VecX v = eig.eigenvectors().col(k);
    if (lambda > 1e-12 * largest && lambda > 0.0) {
      inverse += v * v.transpose() / lambda;
    } else {
      unbounded += v.cwiseAbs();  // directions the data do not see at all
    }
  }
  const Eigen::MatrixXd covariance = sigma2 * inverse;
  // Cluster-robust covariance over blocks of correlated residuals (see the header).
  Eigen::MatrixXd robust = Eigen::MatrixXd::Zero(P, P);
  if (kind == IntervalKind::kFisherOrBlocks &&
      e.residual_blocks.size() == static_cast<std::size_t>(e.residuals_m.size())) {
    std::map<int, VecX> scores;  // per block: J_b^T r_b
    for (Eigen::Index i = 0; i < e.residuals_m.size(); ++i) {
      auto [it, fresh] = scores.try_emplace(e.residual_blocks[i], VecX::Zero(P));
      it->second += e.coordinate_jacobian.row(i).transpose() * e.residuals_m(i);
    }
    const double blocks = static_cast<double>(scores.size());
    if (blocks > 1.0) {
      Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(P, P);
      for (const auto& [block, score] : scores) meat += score * score.transpose();
      robust = inverse * meat * inverse * (blocks / (blocks - 1.0));
    }
  }
  // The shift the held discretisation error makes: refitting with it taken out of the residual
  // moves the coordinates by (J^T J)^+ J^T h (Gauss-Newton, at the fit where J^T r is about 0).
  VecX shift = VecX::Zero(P);
  const bool widen = discretisation_error_m && discretisation_error_m->size() == e.residuals_m.size();
  if (widen) shift = inverse * (e.coordinate_jacobian.transpose() * *discretisation_error_m);
  for (Eigen::Index j = 0; j < P; ++j) {
    ParameterEstimate& est = result.estimates[j];
    if (unbounded(j) > 1e-3) continue;
    est.block_robust = robust(j, j) > covariance(j, j);
    const double variance = std::max(covariance(j, j), robust(j, j));
    const double half_width = 1.96 * std::sqrt(variance) + std::abs(shift(j));  // in the search coordinate
    if (widen) est.discretisation_shift = from_search_coordinate(est.parameter, result.coordinates(j) + shift(j)) - est.value;
    const double y = result.coordinates(j);
    est.lower95 = from_search_coordinate(est.parameter, y - half_width);
    est.upper95 = from_search_coordinate(est.parameter, y + half_width);
    // Logarithmic: within a factor kDeterminedRatio. Linear (effect parameters, whose scale
    // is their meaningful unit): within half a unit.
    est.determined = parameter_scale(est.parameter).logarithmic
                         ? half_width < std::log(ParameterEstimate::kDeterminedRatio)
                         : half_width < 0.5;
  }
  for (Eigen::Index j = 0; j < P && static_cast<std::size_t>(j) < result.at_search_edge.size(); ++j) {
    const int edge = result.at_search_edge[j];
    if (edge == 0) continue;
    ParameterEstimate& est = result.estimates[j];
    const ParameterScale scale = parameter_scale(est.parameter);
    est.at_search_edge = true;
    est.determined = false;
    if (edge < 0) est.lower95 = scale.lower;
    if (edge > 0) est.upper95 = scale.upper;
  }
}

}  // namespace twin
