#pragma once
// The residual field of a fitted twin (issue 6, step 1): one sample per seen marker per marker
// stage, observed minus predicted, with what the structure analysis correlates it with
// (residual_analysis.h): where on the material it is, the predicted sheet normal and curvature
// there, how far it is from the nearest engaged clamp, how loaded the stage is and how long the
// clamps had been still when it was scanned.

#include <optional>
#include <string>
#include <vector>

#include "twin/trials/trial.h"
#include "twin/trials/trial_evaluator.h"
#include "twin/base/types.h"

namespace twin::diagnosis {

struct ResidualSample {
  int trial = 0;   // index into ResidualField::trials
  int stage = 0;   // index into ResidualField::stages (not the trial's own stage index)
  int marker = 0;  // manifest index in its trial
  Vec2 uv_m = Vec2::Zero();           // material coordinates (m)
  Vec3 residual_m = Vec3::Zero();     // observed - predicted (m, world)
  Vec3 observed_m = Vec3::Zero();     // the observed position (m, world)
  Vec3 normal = Vec3::UnitZ();        // predicted unit sheet normal at the marker
  double normal_residual_m = 0.0;     // residual . normal (m): what bending and mass errors move
  double clamp_distance_m = 0.0;      // material distance to the nearest engaged clamp's grip
                                      // patch (m; 0 inside it; +inf when none is engaged)
  double curvature_1_m = 0.0;         // predicted curvature magnitude sqrt(k1^2 + k2^2) (1/m)
  double error_m() const { return residual_m.norm(); }
};

struct FieldTrial {
  std::string name;                 // label (directory name unless given)
  Vec2 sheet_min_uv_m = Vec2::Zero(), sheet_max_uv_m = Vec2::Zero();  // rest mesh bounding box
  std::optional<int> grid_rows, grid_cols;  // marker grid, when the manifest is one
  int marker_count = 0;
};

struct FieldStage {
  int trial = 0;            // index into ResidualField::trials
  int trial_stage = 0;      // index of the stage in its trial
  std::string id;           // the trial's stage id
  std::string label;        // "<trial name>/<stage id>"
  double age_s = 0.0;       // s since the clamps last moved (NaN when unknown), stage_age_s()
  double load_m = 0.0;      // stage_load_m()
  int samples = 0;          // seen markers
  double mean_error_m = 0.0;  // mean |residual| over its samples (the correspondence error mean)
  // Scans of one pose: stages of one trial scanned one after another with the clamps untouched
  // (same_clamp_poses, and no new clamps_moved_at_s) share a pose group, numbered over the field
  // from 0; -1: a stage known to be no other stage's pose (fields made without a trial).
  int pose_group = -1;
};

struct ResidualField {
  std::vector<FieldTrial> trials;
  std::vector<FieldStage> stages;  // marker stages of every trial, in trial then stage order
  std::vector<ResidualSample> samples;  // grouped by stage, in stage then marker order
  int fitted_parameters = 0;  // parameters fitted to these trials (charged in the overall dof)
  int pose_groups = 0;        // FieldStage::pose_group runs from 0 to this - 1

  // Indices of the samples of stage s.
  std::vector<int> samples_of_stage(int s) const;
};

// Seconds since the clamps last moved when stage s was scanned (NaN when unknown): twin/trials/stage_age.h,
// with the trial's clamps_moved_at_s where given.
double stage_age_s(const Trial& trial, int stage);

// How hard the stage pulls on the sheet: the highest engaged clamp's lift above the mean
// height of the clamps engaged at the first stage (m; may be negative).
double stage_load_m(const Trial& trial, int stage);

// A field trial named `name` on `mesh`: its rest bounding box; no marker grid, no markers yet.
FieldTrial field_trial_on(const SheetMesh& mesh, const std::string& name);

// Material distance from uv to the clamp's grip patch (m; 0 inside it).
double grip_patch_distance_m(const ClampSpec& clamp, const Vec2& uv);

// Appends the residuals of one evaluated trial. `fit` must come from `evaluator` and be usable
// (throws std::invalid_argument otherwise, naming the trial). Stages without markers are
// skipped. `name` defaults to the last component of the trial's directory.
void add_trial_residuals(ResidualField& field, const TrialEvaluator& evaluator, const TrialFit& fit,
                         const std::string& name = "");

// Per-vertex curvature magnitude sqrt(k1^2 + k2^2) (1/m) of the sheet at positions x: the
// curvature tensor from the gradient of the vertex normals over each triangle, averaged over
// the vertex's triangles.
std::vector<double> vertex_curvatures_1_m(const SheetMesh& mesh, const VecX& x);

// Per-vertex unit normals (area-weighted) of the sheet at positions x.
std::vector<Vec3> vertex_normals(const SheetMesh& mesh, const VecX& x);

}  // namespace twin::diagnosis
