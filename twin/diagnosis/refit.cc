#include "twin/diagnosis/refit.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

namespace twin::diagnosis {

double SetScore::rms_m() const { return residual_count > 0 ? std::sqrt(sum_squares_m2 / residual_count) : NAN; }

SetScore score_set(const std::vector<TrialEvaluator*>& trials, const Material& material,
                   const std::vector<MaterialParameter>& parameters, ResidualField* field) {
  SetScore s;
  int marker_stages = 0;
  for (TrialEvaluator* t : trials) {
    t->clear_warm_starts();
    const TrialFit fit = t->evaluate(material, parameters);
    const std::string name = std::filesystem::path(t->trial().directory).filename().string();
    if (!fit.usable()) {
      s.failure = fmt::format("{}: {}", t->trial().directory, fit.failure);
      return s;
    }
    for (const StageFit& stage : fit.stages) {
      StageScore row{name, stage.id, NAN, stage.nearest.mean_m};
      if (stage.correspondence) {
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

Refit refit_candidate(const CandidateEffect& effect, const std::vector<TrialEvaluator*>& training,
                      const std::vector<TrialEvaluator*>& testing, const Material& base_fit, double sigma_m,
                      const RefitOptions& options, const std::function<void(const std::string&)>& progress) {
  Refit r;
  r.effect = effect.name;
  for (TrialEvaluator* t : training) t->clear_warm_starts();
  const Material start = null_material(effect, base_fit);
  IdentificationProblem problem(training, start, effect.refit_parameters);
  int count = 0;
  if (progress) {
    problem.on_evaluation = [&](const VecX&, const IdentificationProblem::Evaluation& e) {
      progress(e.usable() ? fmt::format("  refit {} eval {:3d}  rms {:.3f} mm  ({:.2f} s)", effect.name, ++count,
                                        1e3 * std::sqrt(e.mean_square_m2), e.seconds)
                          : fmt::format("  refit {} eval {:3d}  failed: {}", effect.name, ++count, e.failure));
    };
  }
  GradientOptions gradient;
  gradient.max_evaluations = options.max_evaluations;
  gradient.start_coordinates = problem.coordinates_of(start);
  r.result = identify_gradient(problem, gradient);
  if (r.result.coordinates.size() == 0) {
    r.failure = "no result: " + r.result.stop_reason;
    return r;
  }
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
  return r;
}

}  // namespace twin::diagnosis
