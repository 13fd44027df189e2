#include "sim_hw/blind_trial_set.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "twin/base/atomic_file.h"

namespace sim_hw {
namespace {

namespace fs = std::filesystem;

// A reference simulation can fail for an unlucky protocol (a clamp move the solver cannot
// follow); the lab then repeats the trial with the next protocol, as a real lab would.
constexpr int kAttemptsPerTrial = 3;

ScannerLabConfig lab_config(const BlindSetConfig& config, const HiddenEffect& hidden, std::uint64_t lab_seed) {
  ScannerLabConfig lab;
  lab.specimen = config.specimen;
  lab.seed = lab_seed;
  lab.truth_model = config.truth_model;
  lab.grid_spacing_m = config.grid_spacing_m;
  lab.jaws = config.jaws;
  lab.reference_triangles = config.triangles;
  lab.reference_resolves_jaws = false;  // a twin reference is the twin's own mesh (blind_trial_set.h)
  lab.raw_scans = config.raw_scans;
  lab.material_override = hidden.truth;
  lab.creases = hidden.creases;
  return lab;
}

// Trial k's lab seeds: derived from the set's seed only, never from the effect, so the clamp
// protocols say nothing about what is hidden.
std::uint64_t lab_seed(std::uint64_t seed, std::size_t trial, int attempt) {
  return derived_seed(seed, 100 + 10 * trial + static_cast<std::uint64_t>(attempt));
}

// True when `directory` is `base` or below it (after resolving "..", links and separators).
bool inside(const fs::path& directory, const fs::path& base) {
  const fs::path d = fs::weakly_canonical(fs::absolute(directory)).lexically_normal();
  const fs::path b = fs::weakly_canonical(fs::absolute(base)).lexically_normal();
  const fs::path relative = d.lexically_relative(b);
  return !relative.empty() && *relative.begin() != "..";
}

// How far the effect moves the markers: the same trial (same lab seed, protocol and noise)
// without it, mean distance between the noise-free markers over all stages. NaN when the plain
// sheet cannot be simulated on that protocol.
double effect_shift_m(const BlindTrialSet& set, std::size_t k, const LabSpecimen& specimen) {
  ScannerLabConfig plain = set.labs[k];
  plain.material_override = specimen.truth;
  plain.creases.clear();
  plain.raw_scans = false;
  try {
    const LabTrial without = make_lab_trial(plain);
    double sum = 0.0;
    long count = 0;
    for (std::size_t s = 0; s < without.true_markers_m.size(); ++s) {
      for (std::size_t m = 0; m < without.true_markers_m[s].size(); ++m) {
        sum += (set.trials[k].true_markers_m[s][m] - without.true_markers_m[s][m]).norm();
        ++count;
      }
    }
    return sum / static_cast<double>(count);
  } catch (const std::runtime_error&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace

const std::vector<std::string>& blind_trial_names() {
  static const std::vector<std::string> names = {"train_1", "train_2", "test_1"};
  return names;
}

double typical_marker_curvature_1_m(const LabTrial& lab) {
  const twin::Trial& t = lab.trial;
  if (!t.marker_grid_rows || !t.marker_grid_cols) throw std::invalid_argument("typical curvature: markers are not a grid");
  const int rows = *t.marker_grid_rows, cols = *t.marker_grid_cols;
  if (rows < 3 || cols < 3) throw std::invalid_argument("typical curvature: the marker grid needs 3 rows and columns");
  // Second difference over three markers a, b, c in a row or a column, spaced s apart at rest:
  // |x_a - 2 x_b + x_c| / s^2 is the curvature along that line (for small s).
  const auto along = [&](const std::vector<twin::Vec3>& x, int a, int b, int c) {
    const double s = 0.5 * (t.marker_uv_m[c] - t.marker_uv_m[a]).norm();
    return (x[a] - 2.0 * x[b] + x[c]).norm() / (s * s);
  };
  double sum = 0.0;
  long count = 0;
  for (const auto& x : lab.true_markers_m) {
    for (int r = 1; r + 1 < rows; ++r) {
      for (int c = 1; c + 1 < cols; ++c) {
        const int m = r * cols + c;
        // Both directions, so a cylinder of radius R along either direction gives 1/R.
        const double ku = along(x, m - 1, m, m + 1), kv = along(x, m - cols, m, m + cols);
        sum += ku * ku + kv * kv;
        ++count;
      }
    }
  }
  if (count == 0) throw std::invalid_argument("typical curvature: no noise-free markers");
  return std::sqrt(sum / static_cast<double>(count));
}

BlindTrialSet make_blind_trial_set(const BlindSetConfig& config) {
  const LabSpecimen specimen = lab_specimen(config.specimen);
  const std::string effect = config.forced_effect.value_or(effect_for_seed(config.seed));
  const auto make_trial = [&](const HiddenEffect& hidden, std::size_t k, ScannerLabConfig* used) {
    std::string failures;
    for (int attempt = 0; attempt < kAttemptsPerTrial; ++attempt) {
      ScannerLabConfig lab = lab_config(config, hidden, lab_seed(config.seed, k, attempt));
      try {
        LabTrial trial = make_lab_trial(lab);
        if (used) *used = lab;
        return trial;
      } catch (const std::runtime_error& e) {
        failures += fmt::format("{}{}", failures.empty() ? "" : "; ", e.what());
      }
    }
    throw std::runtime_error(fmt::format("blind set (seed {}): trial {} failed {} times: {}", config.seed,
                                         blind_trial_names()[k], kAttemptsPerTrial, failures));
  };
  // Only stiffening needs to know the curvatures the trials reach: the first trial's, without it.
  const auto typical_curvature = [&] {
    HiddenEffect plain;
    plain.effect = "none";
    plain.truth = specimen.truth;
    return typical_marker_curvature_1_m(make_trial(plain, 0, nullptr));
  };
  BlindTrialSet set;
  set.seed = config.seed;
  set.forced = config.forced_effect.has_value();
  set.hidden = draw_hidden_effect(config.seed, effect, specimen, typical_curvature);
  set.names = blind_trial_names();
  set.labs.resize(set.names.size());
  for (std::size_t k = 0; k < set.names.size(); ++k) set.trials.push_back(make_trial(set.hidden, k, &set.labs[k]));
  if (config.measure_effect && set.hidden.effect != "none") {
    for (std::size_t k = 0; k < set.trials.size(); ++k) set.effect_shift_m.push_back(effect_shift_m(set, k, specimen));
  }
  return set;
}

void check_blind_directories(const std::string& trials_directory, const std::string& truth_directory) {
  if (inside(truth_directory, trials_directory)) {
    throw std::invalid_argument(fmt::format("blind set: the truth directory '{}' is inside the trials directory '{}'",
                                            truth_directory, trials_directory));
  }
}

void write_blind_trial_set(const BlindTrialSet& set, const std::string& trials_directory,
                           const std::string& truth_directory) {
  check_blind_directories(trials_directory, truth_directory);
  for (std::size_t k = 0; k < set.trials.size(); ++k) {
    write_lab_trial(set.trials[k], set.labs[k], (fs::path(trials_directory) / set.names[k]).string(),
                    (fs::path(truth_directory) / set.names[k]).string());
  }
  nlohmann::json parameters = nlohmann::json::object();
  for (const auto& [name, value] : set.hidden.parameters) parameters[name] = value;
  nlohmann::json hidden = {{"effect", set.hidden.effect},
                                 {"description", set.hidden.description},
                                 {"parameters", parameters},
                                 {"trials", set.names},
                                 {"forced", set.forced},
                                 {"seed", set.seed},
                                 {"specimen", set.labs.front().specimen},
                                 {"truth_model", to_string(set.labs.front().truth_model)},
                                 {"reference", set.trials.front().reference_description}};
  if (set.labs.front().truth_model == TruthModel::kTwin) hidden["reference_triangles"] = set.labs.front().reference_triangles;
  if (!set.effect_shift_m.empty()) {
    nlohmann::json shift = nlohmann::json::object();
    double sum = 0.0;
    for (std::size_t k = 0; k < set.effect_shift_m.size(); ++k) {
      shift[set.names[k]] = std::isfinite(set.effect_shift_m[k]) ? nlohmann::json(1e3 * set.effect_shift_m[k]) : nullptr;
      sum += set.effect_shift_m[k];
    }
    shift["mean"] = std::isfinite(sum) ? nlohmann::json(1e3 * sum / static_cast<double>(set.effect_shift_m.size())) : nullptr;
    hidden["marker_shift_mm"] = shift;
  }
  twin::write_file_atomically(fs::path(truth_directory) / "hidden_effect.json",
                              [&](std::ostream& out) { out << hidden.dump(2) << "\n"; });
  twin::write_material_file((fs::path(truth_directory) / "material.json").string(), set.hidden.truth);
}

}  // namespace sim_hw
