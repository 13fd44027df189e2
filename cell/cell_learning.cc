// CellController's learning (issue 35): settled states from the tracked cycles, calibrations of
// the material on them and diagnoses of what the twin misses on them on an idle-priority worker,
// an adopted material swapped into the twin on its own worker between steps, and the
// CELL_CALIBRATION and CELL_DIAGNOSIS messages.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "cell/cell_controller.h"
#include "cell/learning/cell_trial.h"
#include "drivers/lcm_channels.h"
#include <prepreg_lcm/calibration_t.hpp>
#include <prepreg_lcm/diagnosis_t.hpp>
#include "twin/base/atomic_file.h"
#include "twin/base/cancellation.h"
#include "twin/diagnosis/svg_figures.h"
#include "twin/model/material_parameters.h"

namespace cell {
namespace {

namespace fs = std::filesystem;

prepreg_lcm::calibration_t calibration_message(std::int64_t utime, std::int64_t id,
                                               const learning::CalibrationResult& r,
                                               const std::string& material_file) {
  prepreg_lcm::calibration_t m;
  m.utime = utime;
  m.calibration_id = id;
  m.verdict = learning::verdict_name(r.verdict);
  m.reason = r.reason;
  m.num_parameters = static_cast<std::int32_t>(r.estimates.size());
  for (const twin::ParameterEstimate& e : r.estimates) {
    m.parameter_names.emplace_back(twin::parameter_name(e.parameter));
    m.values.push_back(e.value);
    m.lower95.push_back(e.lower95);
    m.upper95.push_back(e.upper95);
    m.determined.push_back(e.determined);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const bool before = r.before.failure.empty() && r.before.held_out_mean_m > 0;
  const bool after = r.after.failure.empty() && r.after.held_out_mean_m > 0;
  m.held_out_error_before_m = before ? r.before.held_out_mean_m : nan;
  m.held_out_error_after_m = after ? r.after.held_out_mean_m : nan;
  m.fitted_rms_before_m = before ? r.before.fitted_rms_m : nan;
  m.fitted_rms_after_m = after ? r.after.fitted_rms_m : nan;
  m.states_fitted = r.fitted_states;
  m.states_held_out = r.held_out_states;
  m.simulations = r.simulations;
  m.seconds = r.seconds;
  m.material_file = material_file;
  return m;
}

// report.md of one calibration: what was fitted, to what, and the verdict with its numbers.
std::string calibration_report(std::int64_t id, const learning::CalibrationResult& r, const twin::Material& current,
                               const std::string& material_file) {
  std::string s = fmt::format("# Cell calibration {}: {}\n\n{}\n\n", id, learning::verdict_name(r.verdict), r.reason);
  s += fmt::format("Fitted {} settled state(s), held out the newest ({} whole simulations, {:.1f} s). Fit: {}\n\n",
                   r.fitted_states, r.simulations, r.seconds, r.fit.empty() ? "none" : r.fit);
  if (!r.estimates.empty()) {
    s += "| parameter | current | fitted | 95 % interval | determined |\n|---|---|---|---|---|\n";
    for (const twin::ParameterEstimate& e : r.estimates) {
      s += fmt::format("| {} | {:.4g} | {:.4g} | [{:.4g}, {:.4g}] | {} |\n", twin::parameter_name(e.parameter),
                       twin::get_parameter(current, e.parameter), e.value, e.lower95, e.upper95,
                       e.determined ? "yes" : "no (kept as it was)");
    }
    s += "\n";
  }
  if (r.verdict == learning::CalibrationVerdict::kFailed && r.before.held_out_mean_m == 0.0) return s;
  const auto scores = [](const learning::StateScores& x) {
    return x.failure.empty() ? fmt::format("held-out state {:.2f} mm mean, {:.2f} mm max; fitted states RMS {:.2f} mm",
                                           1e3 * x.held_out_mean_m, 1e3 * x.held_out_max_m, 1e3 * x.fitted_rms_m)
                             : "did not simulate: " + x.failure;
  };
  s += fmt::format("- current material: {}\n- candidate: {}\n", scores(r.before), scores(r.after));
  if (!material_file.empty()) s += fmt::format("- written: {}\n", material_file);
  if (!r.before.stage_mean_m.empty() || !r.after.stage_mean_m.empty()) {
    s += "\n![mean error per state, current material and candidate](states.svg)\n";
  }
  return s;
}

// states.svg: per state, the mean vertex error with the current material and the candidate; the
// held-out state is the last, labelled so.
std::string states_figure(const learning::CalibrationResult& r, const std::vector<learning::SettledObservation>& states) {
  std::vector<twin::diagnosis::BarGroup> groups;
  double noise_mm = 0.0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    twin::diagnosis::BarGroup g;
    g.label = fmt::format("s{}{}", k + 1, k + 1 == states.size() ? " (held out)" : "");
    for (const learning::StateScores* x : {&r.before, &r.after}) {
      g.values.push_back(k < x->stage_mean_m.size() ? 1e3 * x->stage_mean_m[k] : std::nan(""));
    }
    groups.push_back(std::move(g));
    noise_mm = std::max(noise_mm, 1e3 * states[k].mean_noise_m);
  }
  return twin::diagnosis::bar_chart_svg("mean vertex error per settled state (mm)", {"current material", "candidate"},
                                        groups, noise_mm, "tracker scatter of a state's mean");
}

prepreg_lcm::diagnosis_t diagnosis_message(std::int64_t utime, std::int64_t id, const learning::DiagnosisResult& r) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  prepreg_lcm::diagnosis_t m;
  m.utime = utime;
  m.diagnosis_id = id;
  const twin::diagnosis::DiagnoseOutcome& o = r.outcome;
  m.verdict = r.ran ? o.verdict.verdict : "failed";
  m.effect = !r.ran ? "" : o.verdict.effect ? *o.verdict.effect : o.verdict.closest ? *o.verdict.closest : "";
  m.adoption = learning::adoption_name(r.adoption);
  m.reason = r.reason;
  const auto mean = [&](const twin::diagnosis::SetScore* set) {
    return r.ran && set && set->usable() ? set->mean_correspondence_m : nan;
  };
  m.noise_sigma_m = r.ran ? o.sigma_m : nan;
  m.base_fitted_mean_m = mean(&o.base_train);
  m.base_held_out_mean_m = mean(&o.base_test);
  m.effect_fitted_mean_m = mean(o.after_train ? &*o.after_train : nullptr);
  m.effect_held_out_mean_m = mean(o.after_test ? &*o.after_test : nullptr);
  if (r.ran) {
    for (const twin::ParameterEstimate& e : o.parameters) {
      if (!std::isfinite(e.value) || !(e.lower95 <= e.value && e.value <= e.upper95)) continue;
      m.parameter_names.emplace_back(twin::parameter_name(e.parameter));
      m.values.push_back(e.value);
      m.lower95.push_back(e.lower95);
      m.upper95.push_back(e.upper95);
    }
  }
  m.num_parameters = static_cast<std::int32_t>(m.values.size());
  const bool judged = r.before.failure.empty() && r.before.held_out_mean_m > 0;
  m.held_out_error_before_m = judged ? r.before.held_out_mean_m : nan;
  m.held_out_error_after_m = judged && r.after.failure.empty() && r.after.held_out_mean_m > 0 ? r.after.held_out_mean_m : nan;
  m.states = r.states;
  m.seconds = r.seconds;
  m.report_directory = r.ran ? r.report_directory : "";
  m.material_file = r.material_file;
  return m;
}

}  // namespace

std::string CellController::learning_directory() const {
  if (!learning_dir_.empty()) return learning_dir_;
  return (fs::temp_directory_path() / fmt::format("prepreg_cell_learning_{}", ::getpid())).string();
}

void CellController::learn_from_cycle(const CycleReport& report) {
  if (!config_.learning.record_states || !twin_) return;
  collect_calibration();
  collect_diagnosis();
  collect_branch_job();
  if (!settled_detector_) {
    settled_detector_ = std::make_unique<learning::SettledStateDetector>(
        twin_->mesh().vertex_count(), static_cast<int>(plan_.grasps.size()), config_.cell.cycle_hz,
        config_.learning.settle);
  }
  std::vector<char> engaged;
  for (int k = 0; k < static_cast<int>(plan_.grasps.size()); ++k) engaged.push_back(twin_->engaged(k) ? 1 : 0);
  static const std::vector<twin::Vec3> kNone;
  static const std::vector<std::uint8_t> kNoFlags;
  std::optional<learning::SettledObservation> state =
      report.tracked ? settled_detector_->add_cycle(steady_s() - started_s_, report.cycle, grasp_positions(), engaged,
                                                    last_track_.vertices_m, last_track_.vertex_observed)
                     : settled_detector_->add_cycle(steady_s() - started_s_, report.cycle, grasp_positions(), engaged,
                                                    kNone, kNoFlags);
  if (state) {
    // Fake hardware: the true sheet as the window ended (it is published a few times a second
    // and the sheet is settled, so the newest is the state's).
    const std::int64_t truth_age_us = drivers::host_clock_us() - truth_host_us_;
    if (!truth_.empty() && truth_host_us_ > 0 && truth_age_us < 1'000'000) state->truth_m = truth_;
    settled_states_.add(std::move(*state));
    consider_reseed(settled_states_.states().back());
  }
  start_calibration();
  start_diagnosis();
}

void CellController::consider_reseed(const learning::SettledObservation& state) {
  if (!config_.learning.follow_branches || branch_job_.valid() || pending_state_ || !twin_problem_.empty()) return;
  // Once per way of holding the sheet: a refused attempt is not repeated every window.
  if (settled_states_.added() == reseed_tried_at_added_) return;
  // How far the twin's newest prediction is from the settled sheet, over the vertices kept.
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < state.vertices_m.size(); ++i) {
    if (!state.vertices_m[i].allFinite() || prediction_.size() < 3 * static_cast<Eigen::Index>(i) + 3) continue;
    sum += (prediction_.segment<3>(3 * static_cast<Eigen::Index>(i)) - state.vertices_m[i]).norm();
    ++count;
  }
  const double error_m = count > 0 ? sum / count : 0.0;
  if (!(error_m > std::max(config_.learning.reseed_min_error_m, 5.0 * state.mean_noise_m))) return;
  reseed_tried_at_added_ = settled_states_.added();
  std::vector<twin::ClampPose> poses(plan_.grasps.size());
  for (std::size_t g = 0; g < poses.size(); ++g) {
    poses[g].position_m = state.grasp_positions_m[g];
    poses[g].rotation = twin_->jaw_rotation();
    poses[g].engaged = state.engaged[g] != 0;
  }
  branch_job_ = branch_worker_.submit([mesh = twin_->mesh(), material = material_, clamps = plan_.clamp_specs(), poses,
                                       current = prediction_, observed = state.vertices_m,
                                       added = settled_states_.added(), grasps = state.grasp_positions_m,
                                       engaged = state.engaged, flag = calibration_cancelled_] {
    omp_set_num_threads(1);
    const twin::CancellationScope cancellation(flag.get());
    BranchJob job;
    job.candidate = learning::equilibrium_near_observation(mesh, material, clamps, poses, current, observed);
    job.added = added;
    job.grasp_positions_m = grasps;
    job.engaged = engaged;
    return job;
  });
}

void CellController::collect_branch_job() {
  if (!branch_job_.valid() || branch_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  BranchJob job;
  try {
    job = branch_job_.get();
  } catch (const std::exception& e) {
    job.candidate.problem = e.what();
  }
  ++reseed_attempts_;
  // Taken only for the way the sheet is still held: no new settled state since, the engaged
  // grasps within 5 mm of where they were, none released or gripped.
  bool same = job.added == settled_states_.added();
  const std::vector<twin::Vec3> now = grasp_positions();
  for (std::size_t g = 0; same && g < now.size(); ++g) {
    same = (twin_->engaged(static_cast<int>(g)) ? 1 : 0) == job.engaged[g] &&
           (!job.engaged[g] || (now[g] - job.grasp_positions_m[g]).norm() <= 0.005);
  }
  last_reseed_taken_ = same && job.candidate.better(config_.learning.reseed_min_gain);
  if (last_reseed_taken_) pending_state_ = std::move(job.candidate.x);
  job.candidate.x.resize(0);
  last_reseed_ = std::move(job.candidate);
}

void CellController::start_calibration() {
  if (!config_.learning.calibrate || calibration_job_.valid()) return;
  const std::vector<learning::SettledObservation>& states = settled_states_.states();
  if (static_cast<int>(states.size()) < config_.learning.calibration.min_fitted_states + 1) return;
  // Once per new way of holding the sheet: its first settled state is the one held out.
  if (settled_states_.added() == calibrated_at_added_) return;
  calibrated_at_added_ = settled_states_.added();
  const std::int64_t id = calibrations_ + 1;
  const fs::path base = learning_directory();
  learning::CalibrationOptions options = config_.learning.calibration;
  options.cancelled = [flag = calibration_cancelled_] { return flag->load(); };
  calibration_job_ = calibration_worker_.submit(
      [id, directory = base / fmt::format("calibration_{}", id), states, mesh = twin_->mesh(), plan = plan_,
       material = material_, options, flag = calibration_cancelled_] {
        // One thread: the cycle and the twin have the cores; this takes what they leave.
        omp_set_num_threads(1);
        // A cell that stops ends the fit within one Newton iteration (twin/base/cancellation.h).
        const twin::CancellationScope cancellation(flag.get());
        CalibrationJob job;
        job.id = id;
        job.directory = directory.string();
        try {
          const twin::Trial trial =
              learning::write_cell_trial((directory / "trial").string(), states, mesh, plan, material);
          job.result = learning::calibrate_material(trial, material, options);
          if (job.result.verdict == learning::CalibrationVerdict::kAdopted) {
            job.material_file = (directory / "material.json").string();
            twin::write_material_file(job.material_file, job.result.candidate);
          }
          const std::string report = calibration_report(id, job.result, material, job.material_file);
          if (!job.result.before.stage_mean_m.empty() || !job.result.after.stage_mean_m.empty()) {
            const std::string figure = states_figure(job.result, states);
            twin::write_file_atomically(directory / "states.svg", [&](std::ostream& out) { out << figure; });
          }
          twin::write_file_atomically(directory / "report.md", [&](std::ostream& out) { out << report; });
        } catch (const std::exception& e) {  // a file not written, a trial the twin cannot take
          job.result.verdict = learning::CalibrationVerdict::kFailed;
          job.result.reason = e.what();
          job.material_file.clear();
        }
        return job;
      });
}

void CellController::collect_calibration() {
  if (!calibration_job_.valid() || calibration_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  CalibrationJob job;
  try {
    job = calibration_job_.get();
  } catch (const std::exception& e) {
    job.id = calibrations_ + 1;
    job.result.reason = e.what();
  }
  ++calibrations_;
  if (job.result.verdict == learning::CalibrationVerdict::kAdopted) {
    ++calibrations_adopted_;
    pending_material_ = job.result.candidate;  // the twin's worker swaps it in between steps
  }
  bus_.publish(std::string(drivers::channels::kCellCalibration),
               calibration_message(drivers::utime_now(), job.id, job.result, job.material_file));
  last_calibration_ = std::move(job.result);
}

void CellController::start_diagnosis() {
  if (!config_.learning.diagnose || diagnosis_job_.valid() || calibration_job_.valid() || pending_material_) return;
  const std::vector<learning::SettledObservation>& states = settled_states_.states();
  if (static_cast<int>(states.size()) < 3) return;  // two fitted, the newest held out
  // Once per new way of holding the sheet, after its calibration (if any) was collected: the
  // diagnosis starts from the material the twin then runs.
  if (settled_states_.added() == diagnosed_at_added_) return;
  if (config_.learning.calibrate && calibrated_at_added_ != settled_states_.added()) return;
  diagnosed_at_added_ = settled_states_.added();
  const std::int64_t id = diagnoses_ + 1;
  const fs::path base = learning_directory();
  learning::DiagnosisOptions options = config_.learning.diagnosis;
  options.min_gain = config_.learning.calibration.min_gain;
  options.cancelled = [flag = calibration_cancelled_] { return flag->load(); };
  diagnosis_job_ = calibration_worker_.submit([id, directory = base / fmt::format("diagnosis_{}", id), states,
                                               mesh = twin_->mesh(), plan = plan_, material = material_, options,
                                               flag = calibration_cancelled_] {
    omp_set_num_threads(1);
    const twin::CancellationScope cancellation(flag.get());
    DiagnosisJob job;
    job.id = id;
    job.result.directory = directory.string();
    try {
      const twin::Trial trial =
          learning::write_cell_trial((directory / "trial").string(), states, mesh, plan, material);
      job.result = learning::diagnose_states(trial, material, directory.string(), options);
    } catch (const std::exception& e) {  // a file not written, a trial the twin cannot take
      job.result.adoption = learning::EffectAdoption::kFailed;
      job.result.reason = e.what();
    }
    return job;
  });
}

void CellController::collect_diagnosis() {
  if (!diagnosis_job_.valid() || diagnosis_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  DiagnosisJob job;
  try {
    job = diagnosis_job_.get();
  } catch (const std::exception& e) {
    job.id = diagnoses_ + 1;
    job.result.reason = e.what();
  }
  ++diagnoses_;
  if (job.result.adoption == learning::EffectAdoption::kAdopted) {
    ++diagnoses_adopted_;
    pending_material_ = job.result.augmented;  // the twin's worker swaps it in between steps
  }
  bus_.publish(std::string(drivers::channels::kCellDiagnosis), diagnosis_message(drivers::utime_now(), job.id, job.result));
  last_diagnosis_ = std::move(job.result);
}

bool CellController::wait_for_background_learning() {
  bool waited = false;
  // A diagnosis waits on the calibration worker behind the calibration that came before it, and
  // a branch candidate runs on its own worker: each future is awaited where it is.
  const auto await = [&](const auto& job) {
    if (!job.valid()) return;
    job.wait();
    waited = true;
  };
  await(calibration_job_);
  await(diagnosis_job_);
  await(branch_job_);
  return waited;
}

std::string CellController::write_observed_trial(const std::string& directory) const {
  if (!twin_ || settled_states_.states().empty()) return "no settled state recorded";
  try {
    learning::write_cell_trial(directory, settled_states_.states(), twin_->mesh(), plan_, material_);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace cell
