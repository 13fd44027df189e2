#pragma once
// The scanner lab: makes trials the way the paper's experiment did (section 4.2), from a
// reference sheet simulated with the lab's own material on a finer mesh than the twin uses.
//
// Protocol: 17 x 17 raised markers; four clamps, one per edge, at distinct distances from the
// corners; stage 1 holds the sheet slack and roughly level; stages 2-4 each move a different
// clamp up (and toward the centre) by at most 350 mm, stopping before two clamps are farther
// apart than a trial file may say (lab_max_clamp_distance_m); stage 5 releases a clamp.
// Observations: per marker its position with scanner noise, markers under a closed clamp
// hidden (NaN); clamp positions as a contact probe measures them (small noise); optionally the
// raw scan around each seen marker (see marker_scan.h); per stage when its clamps stopped moving and
// when it was scanned, 20 s to 15 min later (clamps_moved_at_s, time_s), which the reference
// sheet's relaxation follows when the truth has it. Everything random comes from the seed.

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "sim_hw/crease.h"
#include "sim_hw/lab_materials.h"
#include "sim_hw/lab_reference.h"
#include "twin/model/shell_model.h"
#include "twin/trials/trial.h"

namespace sim_hw {

struct ScannerLabConfig {
  std::string specimen = "composite";
  std::uint64_t seed = 1;
  // Which physics the "real" sheet follows (lab_reference.h): the reference spline shell
  // (default: it converges, and lab.json carries its own error), the independent plate, or the
  // twin's own model (for comparison: the twin scoring itself).
  TruthModel truth_model = TruthModel::kSplineShell;
  // Spline shell: bisections above its coarsest level (a third of the bending length, at most
  // 2 cm; lab_reference.h).
  int shell_levels = 1;
  // Independent model: the grid's largest spacing (m; 0: the default for the material)
  // and whether the jaws hold the sheet rigidly or let it turn about their centre.
  double grid_spacing_m = 0;
  double path_grid_spacing_m = 0;  // the clamps' path on this coarser grid (0: default)
  real_sheet::JawKind jaws = real_sheet::JawKind::kRigid;
  // Twin model: the reference mesh; the twin should use a coarser one. Refined near the clamps
  // until the jaws are resolved (twin/trials/trial.h: jaw_refinement_radii_m; on 6000 triangles 0.03
  // and 0.015 m, 6760 triangles): the uniform mesh's 2 cm triangles are larger than the jaws
  // (1.5 cm grip radius), so each clamp would hold one triangle or a few vertices, whichever the
  // mesh put there. Or, when radii are given (and reference_resolves_jaws is false), one level
  // per radius (m; refine_near_clamps). Neither: the uniform mesh.
  int reference_triangles = 6000;
  bool reference_resolves_jaws = true;
  std::vector<double> reference_clamp_refinement_radii_m;
  int marker_rows = 17, marker_cols = 17;
  // Scans of each pose: with more than one, the lab scans a pose again later (each after a
  // further 20 s to 15 min, log-uniform) without touching the clamps, as a user who checks
  // repeatability or relaxation does; the stages then share the pose (probed once) and the
  // moment the clamps stopped, with ids "3a", "3b", ... Each scan draws its own marker noise.
  int scans_per_stage = 1;
  double marker_noise_m = 0.3e-3;  // per marker after extraction, each axis (1 sigma)
  double probe_noise_m = 0.05e-3;  // contact probe on the clamps, each axis (1 sigma)
  double clamp_jaw_radius_m = 0.03;  // markers closer than this to a closed clamp are hidden
  bool raw_scans = true;
  double scan_noise_m = 0.1e-3;    // raw scanner points, each axis (1 sigma)
  int scan_points_per_marker = 300;
  // Overrides the specimen's truth (a lab material file, with its effects block).
  std::optional<twin::Material> material_override;
  // Physics outside any material file: creases the ply was once folded along (crease.h), in
  // whichever model simulates the sheet.
  std::vector<Crease> creases;
};

struct LabTrial {
  twin::Trial trial;                             // what a scanner would deliver
  std::vector<std::vector<twin::Vec3>> scans_m;  // per stage, raw scan points (may be empty)
  // Truth, kept out of the trial directory:
  LabSpecimen specimen;
  twin::Material truth;  // what the reference sheet was simulated with
  std::vector<std::vector<twin::Vec3>> true_markers_m;  // per stage, noise-free, all markers
  std::vector<twin::ClampPose> true_stage1_poses;
  int reference_mesh_triangles = 0;  // the twin reference's mesh, refinement included (twin model)
  std::string reference_description;  // the model that made the truth and its resolution
  std::vector<TruthError> truth_error;  // per stage, where the truth model measures its own (lab.json)
};

// How far apart (m) a clamp move may pull two engaged clamps whose material points are
// `sheet_distance_m` apart on the sheet: 1 mm short of what trial files may say
// (twin::max_clamp_distance_m), so the probe's 50 um error never takes a written stage beyond.
double lab_max_clamp_distance_m(double sheet_distance_m);

// The protocol alone, as make_lab_trial draws it first from its seed's generator: the clamps on
// the sheet (material points, jaw radius) and their true poses per stage.
struct LabProtocol {
  std::vector<twin::ClampSpec> clamps;
  std::vector<std::vector<twin::ClampPose>> stages;
};
LabProtocol lab_protocol(double width_m, double height_m, std::mt19937_64& rng);

// The twin model's reference mesh for these clamps (reference_triangles and its refinement).
// Throws std::invalid_argument when both jaws and radii are asked for.
twin::SheetMesh lab_reference_mesh(const ScannerLabConfig& config, double width_m, double height_m,
                                   const std::vector<twin::ClampSpec>& clamps);

// What make_lab_trial draws from the seed before it simulates: the specimen and its truth, the
// trial without stages (sheet, markers, clamps), the stages' true poses and times, and the
// generator as it then stands (it goes on to draw the noise).
struct LabSetup {
  LabSpecimen specimen;
  twin::Material truth;
  twin::Trial trial;
  std::vector<twin::TrialStage> stages;
  std::mt19937_64 rng;
};
LabSetup lab_setup(const ScannerLabConfig& config);
// The reference sheet the config asks for (lab_reference.h).
ReferenceSheet reference_sheet(const ScannerLabConfig& config);

// Throws std::runtime_error if the reference simulation fails (naming the stage).
LabTrial make_lab_trial(const ScannerLabConfig& config);

// Writes the trial into `trial_directory` (trial.json, markers, scans) and the truth (material
// file, noise-free markers, config) into `truth_directory`, which identification never reads.
void write_lab_trial(const LabTrial& lab, const ScannerLabConfig& config,
                     const std::string& trial_directory, const std::string& truth_directory);

}  // namespace sim_hw
