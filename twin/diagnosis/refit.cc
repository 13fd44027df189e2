#include "twin/diagnosis/refit.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/trials/stage_age.h"

namespace twin::diagnosis {

double SetScore::rms_m() const { return residual_count > 0 ? std::sqrt(sum_squares_m2 / residual_count) : NAN; }

SetScore score_set(const std::vector<TrialEvaluator*>& trials, const Material& material,
                   const std::vector<MaterialParameter>& parameters, ResidualField* field, bool continued) {
  SetScore s;
  int marker_stages = 0;
  for (TrialEvaluator* t : trials) {
    if (!continued) t->clear_warm_starts();
    const TrialFit fit = t->evaluate(material, parameters);
    const std::string name = std::filesystem::path(t->trial().directory).filename().string();
    if (!fit.usable()) {
      s.failure = fmt::format("{}: {}", t->trial().directory, fit.failure);
      return s;
    }
    for (const StageFit& stage : fit.stages) {
      StageScore row{name, stage.id, NAN, stage.nearest.mean_m};
      // A stage that saw no marker (a held-out trial's earlier stages, followed for the clamps'
      // path only) has no error to average in.
      if (stage.correspondence && stage.correspondence->points_used > 0) {
        row.correspondence_mean_m = stage.correspondence->mean_m;
        s.mean_correspondence_m += stage.correspondence->mean_m;
        ++marker_stages;
      }
      s.stages.push_back(row);
    }
    if (field) add_trial_residuals(*field, *t, fit, name);
    s.sum_squares_m2 += fit.sum_squares_m2;
    s.residual_count += fit.residual_count;
  }
  s.mean_correspondence_m = marker_stages > 0 ? s.mean_correspondence_m / marker_stages : NAN;
  return s;
}

double bic(double sum_squares_m2, int residual_count, int parameter_count, double sigma_m) {
  return sum_squares_m2 / (sigma_m * sigma_m) + parameter_count * std::log(std::max(residual_count, 1));
}

std::vector<double> marker_stage_ages_s(const std::vector<TrialEvaluator*>& trials) {
  std::vector<double> ages;
  for (const TrialEvaluator* t : trials) {
    const std::vector<TrialStage>& stages = t->trial().stages;
    const std::vector<double> all = stage_load_ages_s(stages);
    for (std::size_t s = 0; s < stages.size(); ++s) {
      if (stages[s].observed.has_markers() && std::isfinite(all[s])) ages.push_back(all[s]);
    }
  }
  return ages;
}

std::vector<Material> refit_starts(const CandidateEffect& effect, const Material& base_fit,
                                   const Eigen::VectorXd& step, const std::vector<double>& stage_ages_s,
                                   const std::optional<ScoreProfilePoint>& profile,
                                   const std::optional<Material>& start_material) {
  std::vector<Material> starts{null_material(effect, base_fit)};
  // Where the score test linearised: the null material, with the profiled parameter at the
  // value whose statistic was taken.
  Material scored = starts.front();
  if (profile) set_parameter(scored, profile->parameter, profile->value);
  const std::vector<MaterialParameter>& p = effect.score_parameters;
  // The one-step estimate, and for effects with signed parameters also its mirror: curvature
  // of either sign bends a hanging sheet alike to first order, so the linearisation's sign is
  // weak evidence.
  const int base_count = static_cast<int>(base_parameters().size());
  bool signed_effect = false;
  for (std::size_t j = base_count; j < p.size(); ++j) signed_effect |= parameter_scale(p[j]).lower < 0.0;
  const bool has_step = step.size() == static_cast<Eigen::Index>(p.size()) && step.allFinite() && step.norm() > 0.0;
  for (const auto& [sign, length] : {std::pair{1.0, 1.0}, std::pair{1.0, 3.0}, std::pair{-1.0, 1.0}}) {
    if ((sign < 0.0 && !signed_effect) || !has_step) continue;
    Material m = scored;
    // In order, as the Jacobian's columns moved them: a paired parameter scales both
    // directions, and its V parameter then scales the warp further.
    for (std::size_t j = 0; j < p.size(); ++j) {
      const ParameterScale scale = parameter_scale(p[j]);
      const double limit = scale.logarithmic ? std::log(8.0) : 8.0;
      const double factor = length * (static_cast<int>(j) >= base_count ? sign : 1.0);
      const double dy = std::clamp(factor * step(static_cast<Eigen::Index>(j)), -limit, limit);
      if (scale.logarithmic) {
        scale_parameter(m, p[j], std::exp(dy));
      } else {
        set_parameter(m, p[j], std::clamp(get_parameter(m, p[j]) + dy * scale.scale, scale.lower, scale.upper));
      }
    }
    starts.push_back(m);
  }
  const bool fits_tau = std::find(effect.refit_parameters.begin(), effect.refit_parameters.end(),
                                  MaterialParameter::kRelaxationTime) != effect.refit_parameters.end();
  if (fits_tau && !stage_ages_s.empty()) {
    const auto [youngest, oldest] = std::minmax_element(stage_ages_s.begin(), stage_ages_s.end());
    const double first = std::max(*youngest, 1.0), last = std::max(*oldest, first);
    // The one-step fraction (the score test assumed the default tau), or 0.3 without a step.
    const double fraction = std::clamp(starts.size() > 1 ? starts[1].effects.relaxation_fraction : 0.3, 0.1, 0.6);
    for (double position : {1.0 / 6.0, 0.5, 5.0 / 6.0}) {
      Material m = starts.size() > 1 ? starts[1] : starts.front();
      m.effects.relaxation_fraction = fraction;
      m.effects.relaxation_time_s = first * std::pow(last / first, position);
      starts.push_back(m);
    }
  }
  if (effect.name == "clamp_grip") {
    // The width saturates (jaws wider than the first ring of vertices grip it whole) and the
    // score test assumed the default: firm jaws at widths spread over the range, on the base
    // fit and on the base fit's own start (refit.h).
    std::vector<Material> without_grip{starts.front()};
    if (start_material) without_grip.push_back(null_material(effect, *start_material));
    for (const Material& from : without_grip) {
      for (double width_m : {0.025, 0.06, 0.12}) {
        Material m = from;
        m.effects.clamp_grip_strength = 1.0;
        m.effects.clamp_grip_width_m = width_m;
        starts.push_back(m);
      }
    }
  }
  if (effect.name == "orthotropic_stiffness") {
    for (double ratio : {0.5, 2.0}) {
      Material m = starts.front();
      const double d = m.bending_rigidity_u_Nm;
      m.bending_rigidity_u_Nm = d / std::sqrt(ratio);
      m.bending_rigidity_v_Nm = d * std::sqrt(ratio);
      starts.push_back(m);
    }
  }
  return starts;
}

const Refit* better_branch(const std::vector<Refit>& refits, const SetScore& base_train, double sigma_m) {
  const Refit* best = nullptr;
  for (const Refit& r : refits) {
    if (!r.usable() || !r.without_effect_train.usable() || !r.without_effect_test.usable() ||
        r.without_effect_train.residual_count != base_train.residual_count) {
      continue;
    }
    if (!best || r.without_effect_train.sum_squares_m2 < best->without_effect_train.sum_squares_m2) best = &r;
  }
  const double charge_m2 = sigma_m * sigma_m * std::log(std::max(base_train.residual_count, 2));
  if (best && best->without_effect_train.sum_squares_m2 < base_train.sum_squares_m2 - charge_m2) return best;
  return nullptr;
}

namespace {

// Refit::RobustPass: `problem` holds no weights before and after.
void robust_pass(IdentificationProblem& problem, const Material& null_start,
                 const std::vector<TrialEvaluator*>& training, const RefitOptions& options, Refit& r,
                 const std::function<void(const std::string&)>& progress) {
  const IdentificationProblem::Evaluation plain =
      problem.evaluate(r.result.coordinates, Derivatives::kNone, 0.5, /*fresh=*/true);
  if (!plain.usable()) return;
  std::vector<std::string> names;
  for (const TrialEvaluator* t : training) {
    const std::string name = std::filesystem::path(t->trial().directory).filename().string();
    names.push_back(name.empty() ? fmt::format("trial {}", names.size() + 1) : name);
  }
  const StageWeights weights = outlier_stage_weights(plain, names);
  if (weights.outliers.empty()) return;
  Refit::RobustPass pass;
  pass.outliers = weights.outliers;
  pass.least_squares_m2 = plain.mean_square_m2;
  if (progress) {
    for (const OutlierStage& o : weights.outliers) {
      progress(fmt::format("  refit {}: stage {}/{} at {:.1f}x the median stage misfit ({:.2f} mm RMS): "
                           "refitting with it down-weighted", r.effect, o.trial, o.stage, o.ratio, 1e3 * o.rms_m));
    }
  }
  GradientOptions gradient;
  gradient.max_evaluations = options.max_evaluations;
  gradient.optimizer = options.optimizer;
  // From the least-squares result and from the effect absent at the base fit, the start every
  // refit has: on blind set 4001 both reached the noise with the stage down-weighted (so did
  // the score test's one-step start, not needed then), and two starts keep the pass's cost
  // at a fraction of the refit's (clamp grip has nine starts).
  const std::vector<VecX> from{r.result.coordinates, problem.coordinates_of(null_start)};
  IdentificationResult weighted;
  {
    // The weights go again however the searches end (an exception included).
    struct Weighted {
      IdentificationProblem& problem;
      ~Weighted() { problem.set_stage_weights({}); }
    } scope{problem};
    problem.set_stage_weights(weights.weights);
    for (std::size_t k = 0; k < from.size(); ++k) {
      if (progress) progress(fmt::format("  robust refit {} from start {} of {}", r.effect, k + 1, from.size()));
      gradient.start_coordinates = from[k];
      IdentificationResult result = identify_gradient(problem, gradient);
      if (result.coordinates.size() == 0) continue;
      if (weighted.coordinates.size() == 0 || result.objective < weighted.objective) weighted = std::move(result);
    }
  }
  if (weighted.coordinates.size() > 0) {
    // The least-squares minimum in the basin the weighted fit found.
    if (progress) progress(fmt::format("  robust refit {}: polishing without weights", r.effect));
    gradient.start_coordinates = weighted.coordinates;
    IdentificationResult polished = identify_gradient(problem, gradient);
    if (polished.coordinates.size() == 0) polished = std::move(weighted);
    const IdentificationProblem::Evaluation fresh =
        problem.evaluate(polished.coordinates, Derivatives::kNone, 0.5, /*fresh=*/true);
    if (fresh.usable()) {
      pass.robust_m2 = fresh.mean_square_m2;
      if (fresh.mean_square_m2 < plain.mean_square_m2) {
        pass.kept = true;
        polished.stop_reason += "; robust refit (stage weights) kept";
        r.result = std::move(polished);
      }
    }
  }
  if (progress) {
    progress(fmt::format("  robust refit {}: {:.3f} mm RMS fresh (least squares: {:.3f} mm), {}", r.effect,
                         1e3 * std::sqrt(pass.robust_m2), 1e3 * std::sqrt(pass.least_squares_m2),
                         pass.kept ? "kept" : "not kept"));
  }
  r.robust = std::move(pass);
}

}  // namespace

IdentificationResult refit_search(const CandidateEffect& effect, const std::vector<TrialEvaluator*>& training,
                                  const Material& starts_front, const Material& start, const RefitOptions& options,
                                  const std::string& label,
                                  const std::function<void(const std::string&)>& progress) {
  IdentificationProblem problem(training, starts_front, effect.refit_parameters);
  int count = 0;
  if (progress) {
    problem.on_evaluation = [&](const VecX&, const IdentificationProblem::Evaluation& e) {
      progress(e.usable() ? fmt::format("  refit {} eval {:3d}  rms {:.3f} mm  ({:.2f} s)", effect.name, ++count,
                                        1e3 * std::sqrt(e.mean_square_m2), e.seconds)
                          : fmt::format("  refit {} eval {:3d}  failed: {}", effect.name, ++count, e.failure));
    };
    progress(fmt::format("  refit {} from {}", effect.name, label));
  }
  for (TrialEvaluator* t : training) t->clear_warm_starts();
  GradientOptions gradient;
  gradient.max_evaluations = options.max_evaluations;
  gradient.optimizer = options.optimizer;
  gradient.start_coordinates = problem.coordinates_of(start);
  return identify_gradient(problem, gradient);
}

Refit refit_candidate(const CandidateEffect& effect, const std::vector<TrialEvaluator*>& training,
                      const std::vector<TrialEvaluator*>& testing, const Material& base_fit,
                      const Eigen::VectorXd& score_step, const std::optional<ScoreProfilePoint>& score_profile,
                      double sigma_m, const RefitOptions& options,
                      const std::function<void(const std::string&)>& progress) {
  const std::vector<Material> starts =
      refit_starts(effect, base_fit, score_step, marker_stage_ages_s(training), score_profile, options.start_material);
  std::vector<IdentificationResult> searches;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    searches.push_back(refit_search(effect, training, starts.front(), starts[k], options,
                                    fmt::format("start {} of {}", k + 1, starts.size()), progress));
  }
  return finish_refit(effect, training, testing, starts, std::move(searches), sigma_m, options, progress);
}

Refit finish_refit(const CandidateEffect& effect, const std::vector<TrialEvaluator*>& training,
                   const std::vector<TrialEvaluator*>& testing, const std::vector<Material>& starts,
                   std::vector<IdentificationResult> searches, double sigma_m, const RefitOptions& options,
                   const std::function<void(const std::string&)>& progress) {
  if (searches.size() != starts.size()) {
    throw std::invalid_argument(fmt::format("finish_refit: {} search results for {} starts", searches.size(), starts.size()));
  }
  Refit r;
  r.effect = effect.name;
  IdentificationProblem problem(training, starts.front(), effect.refit_parameters);
  std::string failures;
  for (IdentificationResult& result : searches) {
    if (result.coordinates.size() == 0) {
      failures += (failures.empty() ? "" : "; ") + result.stop_reason;
      continue;
    }
    if (r.result.coordinates.size() == 0 || result.objective < r.result.objective) r.result = std::move(result);
  }
  if (r.result.coordinates.size() == 0) {
    r.failure = "no result: " + failures;
    return r;
  }
  // The robust pass starts from the kept result's equilibria alone, not from whatever the
  // searches left in the trials' caches: which searches ran in this process, and in what
  // order, depends on how they were spread over ranks.
  for (TrialEvaluator* t : training) t->clear_warm_starts();
  if (options.robust_stages && options.optimizer == GradientOptimizer::kLevenbergMarquardt) {
    robust_pass(problem, starts.front(), training, options, r, progress);
  }
  // The uncertainty at the kept result: its equilibria, not the last start's.
  for (TrialEvaluator* t : training) t->clear_warm_starts();
  estimate_uncertainty(problem, r.result);
  for (std::size_t j = effect.base_count; j < r.result.estimates.size(); ++j) {
    r.effect_estimates.push_back(r.result.estimates[j]);
  }
  r.train_field.fitted_parameters = static_cast<int>(effect.refit_parameters.size());
  r.train = score_set(training, r.result.material, effect.refit_parameters, &r.train_field);
  r.test = score_set(testing, r.result.material, effect.refit_parameters, &r.test_field);
  if (!r.train.usable()) r.failure = r.train.failure;
  else if (!r.test.usable()) r.failure = r.test.failure;
  r.information_criterion = bic(r.train.sum_squares_m2, r.train.residual_count,
                                static_cast<int>(effect.refit_parameters.size()), sigma_m);
  if (r.usable()) {
    // Each trial's cache now holds the refit material's fresh equilibria (score_set above):
    // the effect-free material continues from them, in the same parameter list.
    r.without_effect = null_material(effect, r.result.material);
    r.without_effect_train_field.fitted_parameters = static_cast<int>(effect.base_count);
    r.without_effect_train = score_set(training, r.without_effect, effect.refit_parameters,
                                       &r.without_effect_train_field, /*continued=*/true);
    r.without_effect_test = score_set(testing, r.without_effect, effect.refit_parameters,
                                      &r.without_effect_test_field, /*continued=*/true);
  }
  return r;
}

}  // namespace twin::diagnosis
