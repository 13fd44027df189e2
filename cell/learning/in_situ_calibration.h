#pragma once
// In-situ identification (issue 35): the material fitted to the settled states the cell's own
// cameras saw (a cell trial, cell_trial.h), adopted only when it predicts better a state it was
// not fitted to.
//
// The newest state is held out; the others are fitted (twin identify's gradient method:
// Levenberg-Marquardt on the marker residuals from the current material, 95 % intervals from the
// Fisher / cluster-robust covariance, identification.h). Then the current material and the
// candidate each simulate the whole trial and are scored on the held-out state alone (mean
// distance of its seen markers to their predictions, as PREDICTION_ERROR measures it). The
// candidate is adopted only when it lowers that error by at least min_gain of it and also fits
// the fitted states no worse; otherwise the cell keeps its material and says why.
//
// Held out means not fitted: the held-out state still picks its own equilibrium among those the
// twin can reach from its scan (trial_evaluator.h), as the cell's tracker follows the sheet it
// sees; what it cannot do is move the material.
//
// Pure computation on the caller's thread (the cell runs it on an idle-priority worker); it
// uses as many OpenMP threads as the caller allows (one on the cell's worker).
#include <functional>
#include <string>
#include <vector>

#include "twin/model/material.h"
#include "twin/model/material_parameters.h"
#include "twin/trials/identification.h"
#include "twin/trials/trial.h"

namespace cell::learning {

struct CalibrationOptions {
  std::vector<twin::MaterialParameter> parameters = {twin::MaterialParameter::kTensile, twin::MaterialParameter::kShear,
                                                     twin::MaterialParameter::kBending};
  int min_fitted_states = 2;   // states fitted; the newest is held out on top of them
  double min_gain = 0.10;      // the held-out error must fall by at least this fraction
  int max_evaluations = 12;    // of the Levenberg-Marquardt search
  // Asked after every evaluation of the fit: true ends the calibration (kFailed, "cancelled")
  // within one simulation of the states, so a cell that stops does not wait for a whole fit.
  std::function<bool()> cancelled;
};

// One material scored on a trial's held-out (last) stage and on the stages before it.
struct StateScores {
  std::string failure;  // "" when every stage simulated
  double held_out_mean_m = 0.0, held_out_max_m = 0.0;  // seen markers of the last stage
  double fitted_rms_m = 0.0;  // the other stages' marker residual, RMS per coordinate
  std::vector<double> stage_mean_m;  // per stage, mean distance of its seen markers (m)
};

enum class CalibrationVerdict { kAdopted, kRefused, kFailed };
const char* verdict_name(CalibrationVerdict verdict);  // "adopted", "refused", "failed"

struct CalibrationResult {
  CalibrationVerdict verdict = CalibrationVerdict::kFailed;
  std::string reason;  // why (always set)
  twin::Material candidate;
  std::vector<twin::ParameterEstimate> estimates;  // the fit's values and 95 % intervals
  std::string fit;  // how the fit went: evaluations, why it stopped, its residual
  StateScores before, after;                       // current material, candidate
  int fitted_states = 0, held_out_states = 0;
  int simulations = 0;  // whole-trial simulations, scoring included
  double seconds = 0.0;
};

// Scores `material` on `trial` (the whole trial simulated from flat; the last stage held out).
// Throws std::invalid_argument for a trial of fewer than two stages.
StateScores score_states(const twin::Trial& trial, const twin::Material& material,
                         const std::vector<twin::MaterialParameter>& parameters);

// The adoption rule on two scores (current, candidate): kAdopted or kRefused with the reason.
CalibrationVerdict judge_candidate(const StateScores& before, const StateScores& after, double min_gain,
                                   std::string& reason);

// Fits the material to all stages of `trial` but the last, from `current`, and judges the fit
// on the last. Never throws for numerical trouble (kFailed with the reason); throws
// std::invalid_argument for a trial with fewer than min_fitted_states + 1 stages.
CalibrationResult calibrate_material(const twin::Trial& trial, const twin::Material& current,
                                     const CalibrationOptions& options = {});

// Judges a given candidate (no fit) the same way: for a material from elsewhere, and for tests.
CalibrationResult judge_material(const twin::Trial& trial, const twin::Material& current,
                                 const twin::Material& candidate, const CalibrationOptions& options = {});

}  // namespace cell::learning
