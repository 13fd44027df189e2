#include "cell/learning/in_situ_diagnosis.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "cell/learning/seconds_since.h"

namespace cell::learning {
namespace {

namespace fs = std::filesystem;

// Progress lines are where the diagnosis can be told to stop (it has no other hook): thrown
// through run_diagnosis, which owns nothing that outlives it.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace

const char* adoption_name(EffectAdoption adoption) {
  switch (adoption) {
    case EffectAdoption::kAdopted:
      return "adopted";
    case EffectAdoption::kNotNamed:
      return "not named";
    case EffectAdoption::kRefused:
      return "refused";
    case EffectAdoption::kFailed:
      break;
  }
  return "failed";
}

void write_diagnosis_trials(const twin::Trial& observed, const std::string& directory) {
  if (observed.stages.size() < 3) {
    throw std::invalid_argument(fmt::format(
        "{}: {} settled state(s); a diagnosis fits at least two and holds out the newest", observed.directory,
        observed.stages.size()));
  }
  twin::Trial train = observed;
  train.stages.pop_back();
  twin::write_trial(train, (fs::path(directory) / "train").string());

  twin::Trial held_out = observed;
  const twin::Vec3 not_seen = twin::Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k + 1 < held_out.stages.size(); ++k) {
    twin::TrialStage& stage = held_out.stages[k];
    if (!stage.observed.has_markers()) {
      throw std::invalid_argument(fmt::format("{}: stage {} has no markers (a cell trial has one per vertex)",
                                              observed.directory, stage.id));
    }
    for (twin::Vec3& p : stage.observed.markers_m) p = not_seen;
  }
  twin::write_trial(held_out, (fs::path(directory) / "held_out").string());
}

DiagnosisResult diagnose_states(const twin::Trial& observed, const twin::Material& current,
                                const std::string& directory, const DiagnosisOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  DiagnosisResult r;
  r.states = static_cast<int>(observed.stages.size());
  r.directory = directory;
  r.report_directory = (fs::path(directory) / "report").string();
  write_diagnosis_trials(observed, directory);  // throws for fewer than three states
  const std::string material_path = (fs::path(directory) / "current_material.json").string();
  twin::write_material_file(material_path, current);

  twin::diagnosis::DiagnoseOptions o;
  o.train = {(fs::path(directory) / "train").string()};
  o.test = {(fs::path(directory) / "held_out").string()};
  o.report = r.report_directory;
  o.material = material_path;
  o.path_triangles = 0;  // the clamps' path on the cell's own mesh, as the calibration follows it
  o.discretisation_check = false;  // header: the cell's mesh has no finer twin by triangle count
  o.noise_mm = options.noise_mm;
  o.effects = options.effects;
  o.refits = options.refits;
  o.base_evaluations = options.base_evaluations;
  o.refit_evaluations = options.refit_evaluations;
  o.progress = [&options](const std::string& line) {
    if (options.cancelled && options.cancelled()) throw Cancelled();
    if (options.progress) options.progress(line);
  };
  try {
    r.outcome = twin::diagnosis::run_diagnosis(o);
  } catch (const std::exception& e) {  // a simulation that failed, cancellation, out of memory
    r.reason = std::string("the diagnosis stopped: ") + e.what();
    r.seconds = seconds_since(t0);
    return r;
  }
  r.ran = true;
  const twin::diagnosis::Verdict& v = r.outcome.verdict;
  if (v.verdict != "effect" || !v.effect) {
    r.adoption = EffectAdoption::kNotNamed;
    r.reason = fmt::format("no effect named ({}): {}", v.verdict, v.summary);
    r.seconds = seconds_since(t0);
    return r;
  }
  // Named: the augmented material (the base fit with the effect) must also beat the material the
  // cell runs on the held-out state, by the calibration's margin.
  try {
    r.material_file = (fs::path(r.report_directory) / "material_augmented.json").string();
    r.augmented = twin::read_material_file(r.material_file);
    CalibrationOptions judge;
    judge.min_gain = options.min_gain;
    const CalibrationResult judged = judge_material(observed, current, r.augmented, judge);
    r.before = judged.before;
    r.after = judged.after;
    r.adoption = judged.verdict == CalibrationVerdict::kAdopted ? EffectAdoption::kAdopted : EffectAdoption::kRefused;
    r.reason = fmt::format("{} named; {}", *v.effect, judged.reason);
  } catch (const std::exception& e) {
    r.adoption = EffectAdoption::kFailed;
    r.reason = fmt::format("{} named, but not judged: {}", *v.effect, e.what());
  }
  if (r.adoption != EffectAdoption::kAdopted) r.material_file.clear();
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace cell::learning
