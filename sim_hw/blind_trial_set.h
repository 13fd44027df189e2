#pragma once
// Blind trial sets (issue 6): three scanned trials of one specimen with exactly one hidden
// effect (sim_hw/hidden_effect.h), made by the scanner lab from a seed:
//   TRIALS/train_1, TRIALS/train_2, TRIALS/test_1   trial directories (docs/file_formats.md, "Trial directory"),
//                                                   each with its own clamp protocol and noise
//   TRUTH/hidden_effect.json                        {"effect", "description", "parameters",
//                                                    "trials", "forced", "seed", "specimen",
//                                                    "truth_model", "reference",
//                                                    "reference_triangles" (twin truth only),
//                                                    "marker_shift_mm"}
//   TRUTH/material.json                             the material the lab simulated
//   TRUTH/<trial>/                                  per trial: noise-free markers, lab.json
// TRUTH must not be inside TRIALS: whatever analyses TRIALS must not be able to find it.
// The lab's sheet is the reference spline shell by default (lab_reference.h): physics the twin
// does not share, on its own discretisation, converging under refinement, so the gap between
// twin and measurement is the noise plus the twin's model-form and discretisation error (and the
// reference's own error, in each trial's lab.json: docs/reference_sheet.md), as on a real sheet.
// The independent plate stays selectable (its grid error in docs/independent_sheet.md). With truth_model twin, the reference is
// the twin itself on the analysis twin's mesh (`triangles`), and without a hidden effect the
// only gap is the scanner noise: the workflow scored against itself.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim_hw/hidden_effect.h"
#include "sim_hw/scanner_lab.h"

namespace sim_hw {

struct BlindSetConfig {
  std::uint64_t seed = 1;
  std::string specimen = "composite";
  TruthModel truth_model = TruthModel::kSplineShell;
  double grid_spacing_m = 0;                 // independent model (0: its default for the material)
  real_sheet::JawKind jaws = real_sheet::JawKind::kRigid;
  int triangles = 300;                       // twin model: the reference mesh = the twin's
  std::optional<std::string> forced_effect;  // tests and the accuracy script only
  bool raw_scans = false;                    // raw scans are large and diagnose does not read them
  // Also simulate each trial without the effect, to record how far it moves the markers
  // (hidden_effect.json "marker_shift_mm"): doubles the simulations of a set with an effect.
  bool measure_effect = true;
};

struct BlindTrialSet {
  std::uint64_t seed = 0;
  bool forced = false;  // the effect was forced, not picked by the seed
  HiddenEffect hidden;
  std::vector<std::string> names;      // train_1, train_2, test_1
  std::vector<LabTrial> trials;        // in the order of names
  std::vector<ScannerLabConfig> labs;  // how each was made (seeds), for the truth directory
  // Per trial, mean distance (m) between its noise-free markers and those of the same trial
  // without the effect: the effect's size before any refit (a refit of the paper's parameters
  // absorbs part of it). Empty without an effect or measure_effect; NaN where the plain sheet failed.
  std::vector<double> effect_shift_m;
};

// The names of the three trials, in order.
const std::vector<std::string>& blind_trial_names();

// The "typical curvature" (1/m) of the specimen in a trial: RMS over all stages and interior
// markers of sqrt(k_row^2 + k_col^2), with k the second difference of the noise-free markers
// along the grid's row and column through the marker (a cylinder of radius R gives 1/R).
double typical_marker_curvature_1_m(const LabTrial& lab);

// Throws std::runtime_error when a trial's reference simulation fails for every lab seed tried.
BlindTrialSet make_blind_trial_set(const BlindSetConfig& config);

// Throws std::invalid_argument when truth_directory is trials_directory or inside it.
void check_blind_directories(const std::string& trials_directory, const std::string& truth_directory);
// Checks the directories as above, then writes.
void write_blind_trial_set(const BlindTrialSet& set, const std::string& trials_directory,
                           const std::string& truth_directory);

}  // namespace sim_hw
