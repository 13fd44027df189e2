#include "cell/learning/in_situ_calibration.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cell/learning/seconds_since.h"
#include "twin/trials/trial_evaluator.h"

namespace cell::learning {
namespace {

// The trial's own mesh (a cell trial names the twin's rest mesh), unrefined, and the clamps'
// path followed on it: the material is identified on the discretisation the cell runs.
twin::TwinMeshSpec mesh_as_given() {
  twin::TwinMeshSpec spec;
  spec.path_triangles = 0;
  return spec;
}

twin::Trial without_last_stage(twin::Trial trial) {
  trial.stages.pop_back();
  return trial;
}

}  // namespace

const char* verdict_name(CalibrationVerdict verdict) {
  switch (verdict) {
    case CalibrationVerdict::kAdopted:
      return "adopted";
    case CalibrationVerdict::kRefused:
      return "refused";
    case CalibrationVerdict::kFailed:
      break;
  }
  return "failed";
}

StateScores score_states(const twin::Trial& trial, const twin::Material& material,
                         const std::vector<twin::MaterialParameter>& parameters) {
  if (trial.stages.size() < 2) {
    throw std::invalid_argument(fmt::format("score_states: trial {} has {} stage(s); one is held out of at least two",
                                            trial.directory, trial.stages.size()));
  }
  StateScores s;
  twin::TrialEvaluator evaluator(trial, mesh_as_given(), material);
  const twin::TrialFit fit = evaluator.evaluate(material, parameters);
  if (!fit.usable()) {
    s.failure = fit.failure;
    return s;
  }
  double squares = 0.0;
  int coordinates = 0, held_out = 0;
  for (std::size_t k = 0; k < trial.stages.size(); ++k) {
    const std::vector<twin::Vec3>& seen = trial.stages[k].observed.markers_m;
    const std::vector<twin::Vec3>& predicted = fit.stages[k].predicted_markers_m;
    const bool last = k + 1 == trial.stages.size();
    double stage_sum_m = 0.0;
    int stage_seen = 0;
    for (std::size_t m = 0; m < seen.size() && m < predicted.size(); ++m) {
      if (!seen[m].allFinite()) continue;
      const double d = (predicted[m] - seen[m]).norm();
      stage_sum_m += d;
      ++stage_seen;
      if (last) {
        s.held_out_mean_m += d;
        s.held_out_max_m = std::max(s.held_out_max_m, d);
        ++held_out;
      } else {
        squares += d * d;
        coordinates += 3;
      }
    }
    s.stage_mean_m.push_back(stage_seen > 0 ? stage_sum_m / stage_seen : std::nan(""));
  }
  if (held_out == 0 || coordinates == 0) {
    s.failure = "a stage has no seen marker to score";
    return s;
  }
  s.held_out_mean_m /= held_out;
  s.fitted_rms_m = std::sqrt(squares / coordinates);
  return s;
}

CalibrationVerdict judge_candidate(const StateScores& before, const StateScores& after, double min_gain,
                                   std::string& reason) {
  if (!after.failure.empty()) {
    reason = "the candidate does not simulate the states: " + after.failure;
    return CalibrationVerdict::kRefused;
  }
  if (!before.failure.empty()) {
    reason = "the current material does not simulate the states (" + before.failure +
             "); the candidate does: held-out state " + fmt::format("{:.1f} mm mean", 1e3 * after.held_out_mean_m);
    return CalibrationVerdict::kAdopted;
  }
  const double needed_m = (1.0 - min_gain) * before.held_out_mean_m;
  if (!(after.held_out_mean_m < needed_m)) {
    reason = fmt::format(
        "no better on the held-out state: {:.2f} mm mean with the current material, {:.2f} mm with the candidate "
        "(adopted only below {:.2f} mm)",
        1e3 * before.held_out_mean_m, 1e3 * after.held_out_mean_m, 1e3 * needed_m);
    return CalibrationVerdict::kRefused;
  }
  if (!(after.fitted_rms_m <= before.fitted_rms_m)) {
    reason = fmt::format("fits the fitted states worse: RMS {:.2f} mm against {:.2f} mm with the current material",
                         1e3 * after.fitted_rms_m, 1e3 * before.fitted_rms_m);
    return CalibrationVerdict::kRefused;
  }
  reason = fmt::format("held-out state {:.2f} -> {:.2f} mm mean ({:.2f} -> {:.2f} mm max), fitted states RMS "
                       "{:.2f} -> {:.2f} mm",
                       1e3 * before.held_out_mean_m, 1e3 * after.held_out_mean_m, 1e3 * before.held_out_max_m,
                       1e3 * after.held_out_max_m, 1e3 * before.fitted_rms_m, 1e3 * after.fitted_rms_m);
  return CalibrationVerdict::kAdopted;
}

CalibrationResult judge_material(const twin::Trial& trial, const twin::Material& current,
                                 const twin::Material& candidate, const CalibrationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  CalibrationResult r;
  r.candidate = candidate;
  r.fitted_states = static_cast<int>(trial.stages.size()) - 1;
  r.held_out_states = 1;
  r.before = score_states(trial, current, options.parameters);
  r.after = score_states(trial, candidate, options.parameters);
  r.simulations = 2;
  r.verdict = judge_candidate(r.before, r.after, options.min_gain, r.reason);
  r.seconds = seconds_since(t0);
  return r;
}

CalibrationResult calibrate_material(const twin::Trial& trial, const twin::Material& current,
                                     const CalibrationOptions& options) {
  const int stages = static_cast<int>(trial.stages.size());
  if (stages < options.min_fitted_states + 1) {
    throw std::invalid_argument(fmt::format("calibrate_material: {} settled state(s); {} to fit and one to hold out needed",
                                            stages, options.min_fitted_states));
  }
  const auto t0 = std::chrono::steady_clock::now();
  CalibrationResult r;
  r.fitted_states = stages - 1;
  r.held_out_states = 1;
  twin::IdentificationResult fit;
  int fit_simulations = 0;
  try {
    twin::TrialEvaluator fitted(without_last_stage(trial), mesh_as_given(), current);
    twin::IdentificationProblem problem({&fitted}, current, options.parameters);
    if (options.cancelled) {
      problem.on_evaluation = [&](const twin::VecX&, const twin::IdentificationProblem::Evaluation&) {
        if (options.cancelled()) throw std::runtime_error("cancelled");
      };
    }
    twin::GradientOptions search;
    search.optimizer = twin::GradientOptimizer::kLevenbergMarquardt;
    search.max_evaluations = options.max_evaluations;
    fit = twin::identify_gradient(problem, search);
    if (fit.coordinates.size() == 0 || !std::isfinite(fit.objective)) {
      r.reason = "the fit found no material that simulates the states: " + fit.stop_reason;
      r.simulations = problem.simulations();
      r.seconds = seconds_since(t0);
      return r;
    }
    twin::estimate_uncertainty(problem, fit, twin::IntervalKind::kFisherOrBlocks);
    fit_simulations = problem.simulations();
    r.fit = fmt::format("{} evaluations, residual RMS {:.2f} mm per coordinate; {}", fit.evaluations,
                        1e3 * fit.noise_sigma_m, fit.stop_reason);
  } catch (const std::exception& e) {  // e.g. out of memory: the cell keeps its material
    r.reason = std::string("the fit stopped: ") + e.what();
    r.seconds = seconds_since(t0);
    return r;
  }
  // Only what the states pin down changes: a parameter they leave undetermined (its interval
  // spans more than a factor kDeterminedRatio, or the search ran to its edge) keeps the current
  // value. Wandering freely in the fit, it would otherwise carry the candidate anywhere the fitted
  // states cannot see (measured: a fit from a wrong start predicted a released flap 74 mm off
  // with shear and tensile undetermined, against 30 mm for the start).
  if (options.cancelled && options.cancelled()) {
    r.reason = "the fit stopped: cancelled";
    r.seconds = seconds_since(t0);
    return r;
  }
  twin::Material candidate = current;
  std::vector<std::string> kept;
  for (const twin::ParameterEstimate& e : fit.estimates) {
    if (e.determined) {
      twin::set_parameter(candidate, e.parameter, e.value);
    } else {
      kept.emplace_back(twin::parameter_name(e.parameter));
    }
  }
  candidate.name = current.name + " (calibrated in the cell)";
  if (kept.size() == fit.estimates.size()) {
    r.reason = "the states determine none of the parameters; the current material stays";
    r.verdict = CalibrationVerdict::kRefused;
    r.estimates = fit.estimates;
    r.simulations = fit_simulations;
    r.seconds = seconds_since(t0);
    return r;
  }
  if (!kept.empty()) r.fit += fmt::format("; not determined, kept as they were: {}", fmt::join(kept, ", "));
  CalibrationResult judged = judge_material(trial, current, candidate, options);
  judged.estimates = fit.estimates;
  judged.fit = r.fit;
  judged.simulations += fit_simulations;
  judged.seconds = seconds_since(t0);
  return judged;
}

}  // namespace cell::learning
