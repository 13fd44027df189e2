#pragma once
// The discrepancy workflow on the states the cell's own cameras saw (issue 35): find what the
// twin misses on them, name the effect, add it, with exactly the rules of `twin diagnose`
// (twin/diagnosis/diagnose.h, verdict.h), and put the named effect into the twin only when it
// also predicts a state it was not fitted to better (in_situ_calibration.h's judge).
//
// The observed trial (cell_trial.h) is split as diagnosis wants it, training and held out:
//   DIR/train/      every state but the newest
//   DIR/held_out/   every state, the older ones with no vertex seen: the twin follows the clamps'
//                   path through them (a released gripper, a raised one), and only the newest
//                   is scored
//   DIR/current_material.json  the material the cell runs: the diagnosis's start
//   DIR/report/     twin diagnose's verdict.json, report.md with figures, material_augmented.json
// so `twin diagnose --train DIR/train --test DIR/held_out --material DIR/current_material.json
// --path-triangles 0` reruns it offline.
//
// The twin is the trial's own mesh (the cell's), the clamps' path followed on it. The
// discretisation check (a twin of twice the triangles) is not made: the cell's sheet is a mesh
// file, which has no finer twin by triangle count (discretisation_check.h says "not measured").
//
// Noise: the tracker's scatter of a state's mean is not the tracker's error (it slides along the
// surface, and that bias does not average out). Unless `noise_mm` is given (the tracker's error
// per coordinate as measured at commissioning), diagnose estimates the noise from the training
// states as it does for a lab's trials, and the report says so.
//
// Pure computation on the caller's thread (the cell runs it on its background worker).
#include <functional>
#include <string>

#include "cell/learning/in_situ_calibration.h"
#include "twin/diagnosis/diagnose.h"
#include "twin/model/material.h"
#include "twin/trials/trial.h"

namespace cell::learning {

// The candidates a cell's states can carry. Not marker_mass (the cell's "markers" are its mesh's
// vertices: nothing is glued to the sheet) and not viscoelastic_relaxation (each way of holding
// the sheet gives one settled state, so no two scans of one pose at different ages).
inline constexpr const char* kCellEffects =
    "orthotropic_stiffness,rest_curvature,nonlinear_bending,clamp_grip,clamp_slip";

struct DiagnosisOptions {
  std::string effects = kCellEffects;  // comma-separated effect_library names
  double noise_mm = 0.0;               // tracker error per coordinate (mm); 0: estimated
  int refits = 2;                      // candidates refitted, best score first
  int base_evaluations = 12;           // of the base fit (the calibration's budget)
  int refit_evaluations = 12;          // of each start of a refit
  double min_gain = 0.10;              // adoption: as CalibrationOptions::min_gain
  // Asked at every progress line of the diagnosis: true ends it (kFailed, "cancelled").
  std::function<bool()> cancelled;
  std::function<void(const std::string&)> progress;  // diagnose's progress lines
};

enum class EffectAdoption { kAdopted, kNotNamed, kRefused, kFailed };
const char* adoption_name(EffectAdoption adoption);  // "adopted", "not named", "refused", "failed"

struct DiagnosisResult {
  EffectAdoption adoption = EffectAdoption::kFailed;
  std::string reason;     // why adopted or not (always set)
  bool ran = false;       // the diagnosis ran to its verdict (outcome below is set)
  twin::diagnosis::DiagnoseOutcome outcome;
  twin::Material augmented;  // the base fit with the named effect (verdict "effect")
  StateScores before, after;  // current material and augmented on the states (when judged)
  std::string directory, report_directory, material_file;  // material_file: the augmented one
  int states = 0;
  double seconds = 0.0;
};

// Writes DIR/train and DIR/held_out (above) from an observed trial of at least three states.
// Throws std::invalid_argument for fewer, std::runtime_error naming a path it cannot write.
void write_diagnosis_trials(const twin::Trial& observed, const std::string& directory);

// The split above, the diagnosis, and for a named effect the judge. Never throws for numerical
// trouble or a failed simulation (kFailed with the reason); throws std::invalid_argument for a
// trial of fewer than three states.
DiagnosisResult diagnose_states(const twin::Trial& observed, const twin::Material& current,
                                const std::string& directory, const DiagnosisOptions& options = {});

}  // namespace cell::learning
