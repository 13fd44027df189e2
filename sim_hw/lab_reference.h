#pragma once
// The scanner lab's "real" sheet, simulated through a trial's stages by one of three models:
//   spline_shell (the default): the reference shell (sim_hw/spline_shell, shell_reference.h),
//     the lab's material on B-splines, converging under refinement (`reference_refinement`,
//     docs/reference_sheet.md), every trial carrying its own error;
//   independent: sim_hw/real_sheet, physics that shares no mesh, energy or solver code with the
//     twin, on a graded grid whose distance from convergence is measured by
//     `real_sheet_refinement` (docs/independent_sheet.md); its pivot jaws are its own;
//   twin: the twin's own shell model on a reference mesh (the lab before issue 33; every figure
//     against it is the twin scoring itself).
// Either returns, per stage, the noise-free markers and the sheet's normal at each (for the raw
// scans), or throws std::runtime_error naming the stage that failed.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim_hw/crease.h"
#include "sim_hw/real_sheet/jaw_pad.h"
#include "twin/model/material.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/trials/trial.h"

namespace sim_hw {

enum class TruthModel { kIndependent, kTwin, kSplineShell };
// "independent" | "twin" | "spline_shell"; throws std::invalid_argument naming `what` otherwise.
TruthModel parse_truth_model(const std::string& name, const std::string& what);
std::string to_string(TruthModel model);
// "rigid" | "pivot"; throws std::invalid_argument naming `what` otherwise.
real_sheet::JawKind parse_jaw_kind(const std::string& name, const std::string& what);
std::string to_string(real_sheet::JawKind kind);

struct ReferenceSheet {
  TruthModel model = TruthModel::kSplineShell;
  // Independent model: the clamps' path is followed on a coarse grid (path_grid_spacing_m; 0:
  // independent_path_spacing_m) and each stage's equilibrium is then carried to the grid the
  // markers are read from and solved there (grid_spacing_m; 0: the default for the material,
  // independent_grid_spacing_m). The path picks the branch (as a real sheet's handling does);
  // the fine grid refines the shape on it.
  double grid_spacing_m = 0;
  double path_grid_spacing_m = 0;
  real_sheet::JawKind jaws = real_sheet::JawKind::kRigid;
  // Spline shell: degree, level 0's largest span and its span at the jaws' edges (m; 0: for
  // the material, default_shell_span_m() below and half of it), and how many bisections above level 0
  // the markers are read on. For the composite level 0 has 2 cm spans, the coarsest whose folded
  // stages are in the asymptotic range (docs/reference_sheet.md: from 4 cm, folds the 4 and 2 cm
  // levels smeared into bends appeared at 1 cm, and elsewhere the composite's markers still moved
  // 0.4-0.7 mm between 2 and 1 cm; from 2 cm they move 0.2-0.3 mm to 5 mm).
  int shell_degree = 3;
  double shell_span_m = 0, shell_jaw_span_m = 0;
  int shell_levels = 1;
  // The markers the truth's own error is measured over: not within this of a closed clamp (the
  // scanner's hidden radius; a jaw holds the same material at every level).
  double error_hidden_radius_m = 0.03;
  // Twin model: its mesh (ScannerLabConfig's reference mesh settings).
  int triangles = 6000;
  bool resolve_jaws = true;
  std::vector<double> clamp_refinement_radii_m;
};

// The truth's own error at a stage, from its refinement levels (the spline shell's, with one
// level or more above level 0): the markers' change between the two finest levels and, with three
// levels or more on one branch, the observed order and Richardson's estimate of the finest
// level's error (sim_hw/spline_shell/refinement_estimate.h).
struct TruthError {
  double finest_change_mean_m = 0, finest_change_max_m = 0;
  bool one_branch = true;             // the two finest levels hold the same folds
  std::optional<double> order;        // observed
  std::optional<double> estimated_m;  // of the mean, Richardson
  std::string text;                   // per comparison and the estimate, as the study prints it
};

// lab.json's "truth_error": per stage (ids from `stages`), the two finest levels' change, whether
// they hold the same folds, and the observed order and estimate where there are (null otherwise).
nlohmann::json truth_error_json(const std::vector<TruthError>& errors, const std::vector<twin::TrialStage>& stages);

struct ReferenceStages {
  std::vector<std::vector<twin::Vec3>> markers_m, normals;  // per stage, per marker
  std::string description;  // the model and its resolution, for people and lab.json
  int size = 0;             // triangles (twin) or grid nodes (independent)
  std::vector<TruthError> truth_error;  // per stage; empty when the model has no levels to compare
};

// The independent model's default grids for a material, from the bending length
// l = (D / (rho g))^(1/3) of its softer direction: the markers' grid has its largest spacing at
// min(2 cm, 0.3 l), graded to a quarter of that at the jaws and the free edges (grid.h:
// graded_grid); the path's uniform grid min(3 cm, 0.5 l). How far these are from converged is
// measured by real_sheet_refinement (docs/independent_sheet.md).
double independent_grid_spacing_m(const twin::Material& material);
double independent_path_spacing_m(const twin::Material& material);

// The spline shell's level 0 for a material: its largest span a third of the bending length l
// above, at most 2 cm (the composite's l / 3.2, the coarsest level whose folded stages were
// found in the asymptotic range: docs/reference_sheet.md); a fabric of shorter l gets as many
// spans per l. The span at the jaws' edges is half of it.
double default_shell_span_m(const twin::Material& material);

// The twin model's reference mesh for these clamps. Throws std::invalid_argument when both
// jaws and radii are asked for.
twin::SheetMesh twin_reference_mesh(const ReferenceSheet& reference, double width_m, double height_m,
                                    const std::vector<twin::ClampSpec>& clamps);

// Whether a marker is hidden from a scan at a stage: within radius_m (material) of a clamp that
// is closed there (poses in clamp order).
bool hidden_under_clamp(const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::ClampPose>& poses,
                        const twin::Vec2& marker_uv_m, double radius_m);

// Simulates `stages` (poses, times) of a sheet of width x height carrying `marker_uv_m`.
ReferenceStages simulate_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                   const std::vector<Crease>& creases, double width_m, double height_m,
                                   const std::vector<twin::ClampSpec>& clamps,
                                   const std::vector<twin::TrialStage>& stages,
                                   const std::vector<twin::Vec2>& marker_uv_m);

// The independent model's refinement study: one path (on the path grid), its stages carried to
// the graded grid of each spacing of `spacings_m` in turn, coarse to fine (each from the one
// before, so all stay on one branch); per spacing (coarse to fine), the stages' markers.
std::vector<ReferenceStages> independent_refinement(const ReferenceSheet& reference, const twin::Material& truth,
                                                    const std::vector<Crease>& creases, double width_m,
                                                    double height_m, const std::vector<twin::ClampSpec>& clamps,
                                                    const std::vector<twin::TrialStage>& stages,
                                                    const std::vector<twin::Vec2>& marker_uv_m,
                                                    const std::vector<double>& spacings_m,
                                                    double bending_change = 0.0);
// With bending_change != 0 one more entry follows: the finest grid's stages solved again with
// every bending rigidity times (1 + bending_change), from the finest's equilibria (the
// sensitivity of the markers to the material, against which to read the grids' differences).

}  // namespace sim_hw
