#pragma once
// One scanned trial as identification sees it: the twin simulates every stage for a candidate
// material, compares with what was scanned, and (when asked) differentiates the misfit with
// respect to material parameters through each stage's equilibrium (equilibrium_sensitivity.h).
//
// Misfits, per stage (marker_error.h): Algorithm 1 (nearest vertex) and, for marker stages, the
// correspondence error. The smooth misfit that gradients are taken of is the least-squares sum
//   S = sum over observations o of |p(o) - o|^2                                   (m^2)
// with p(o) the prediction of marker o's own material point (marker stages) or, for a stage
// seen as an unordered cloud, the vertex nearest to o (Algorithm 1's pairing, held fixed
// while differentiating). Under independent Gaussian scanner noise, minimising S is maximum
// likelihood, and its Jacobian gives the Fisher covariance of the estimate.
//
// Simulation: the first evaluation follows the trial's stages by quasi-static continuation from
// the flat sheet (trial_simulation.h), and also lets every marker stage go from its scan
// (scan_tether.h), starting once from the shape interpolated from the markers (observed_shape.h)
// and once from the path's equilibrium; per stage it keeps the equilibrium nearest the markers.
// These solves run side by side on two lanes (job_lanes.h), each lane on its own copy of the
// model: the path on one, the scan starts on the other as soon as they can start. A slack
// hanging sheet has many equilibria and the path from flat picks among them by tiny
// differences (mesh, material: a 30 % stiffer bending can fold a corner the other way), so
// the scan is what says which one the real sheet was in.
//   When every stage is a marker stage, the path is followed on a coarse mesh of the sheet
// (TwinMeshSpec::path_triangles) and its equilibria, interpolated onto the twin, are only the
// starts of the second tether: on the twin's own mesh the path was the longest part of a fresh
// simulation (12.5 s on one thread for a lab trial at 2027 triangles, where a whole fresh
// simulation on two lanes took 13.2 s; 58 s at 5012) and its equilibria were never the ones
// kept (12-57 mm from the scans against 1-10 mm tethered). Measured at the
// lab's true material on four lab trials (2027-triangle twin, mean over stages of the kept
// equilibria's marker error): 5.45, 2.21, 1.56, 3.77 mm with the path on the twin; 5.49, 2.17,
// 1.54, 3.79 mm with it on 300 triangles, whose path took 0.6-0.9 s. If a stage then has no
// equilibrium, or a stage is seen only as a cloud (no tether), the path runs on the twin as before.
// Later evaluations start every stage from the equilibrium of the nearest material evaluated
// before, and also from the best-fitting one within one material step when that is another
// (continuation_start.h; the better fit is kept), and carry it to the new material in steps of
// at most a factor kMaterialStepRatio in every varied parameter (continuation in the material
// instead of in the clamps: a few Newton iterations per step instead of a whole trial, and it
// stays on the branch chosen by the scan). If a step fails, or more than kMaxMaterialSteps
// would be needed, the trial is simulated afresh; also when the continued misfit is more than
// kBranchCheckRatio times its start's and a fresh simulation fits better.
//
// Effects that need the trial (model_effects.h): the twin carries the trial's markers (their
// mass, when the material gives them one), and every stage is solved and differentiated at its
// load age (stage_age.h), so a relaxing material is stiffer in a stage scanned soon after a move.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "twin/model/clamp.h"
#include "twin/trials/continuation_start.h"
#include "twin/solvers/equilibrium_sensitivity.h"
#include "twin/trials/marker_error.h"
#include "twin/model/material_parameters.h"
#include "twin/mesh/material_point.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"
#include "twin/trials/trial.h"

namespace twin {

struct StageFit {
  std::string id;
  VecX x;                                    // equilibrium positions (3n, m)
  StageError nearest;                        // Algorithm 1
  std::optional<StageError> correspondence;  // marker stages only
  std::vector<Vec3> predicted_markers_m;     // per manifest marker (marker stages only)
};

enum class Derivatives { kNone, kGradient, kJacobian };

struct TrialFit {
  std::string failure;                 // empty when every stage reached an equilibrium
  bool usable() const { return failure.empty(); }
  std::vector<StageFit> stages;
  double sum_squares_m2 = 0.0;         // S above
  int residual_count = 0;              // scalar residuals in S (3 per observation)
  VecX coordinate_gradient;                   // dS/dy_j (m^2), y the search coordinates (material_parameters.h), with Derivatives::kGradient or kJacobian
  Eigen::MatrixXd coordinate_jacobian;        // d r / dy_j (m), residual_count x P, with kJacobian
  VecX residuals_m;                    // r (residual_count), stacked like the Jacobian's rows
  // Per residual: its stage and the quarter of the sheet its observation lies in, stage * 4 +
  // quarter. Model error is smooth, so residuals in one block are correlated; the blocks are
  // the units of the cluster-robust covariance (identification.h: estimate_uncertainty).
  std::vector<int> residual_blocks;
  bool warm_started = false;
  int stages_from_scan = 0;            // cold start: stages whose equilibrium was found from the scan
  // Cold start: stages predicted on the equilibrium they share with the other scans of their pose
  // (consecutive stages with the same clamp poses).
  int stages_sharing_an_equilibrium = 0;
  int newton_iterations = 0;
  double seconds = 0.0;

  // Paper's stage score summed over stages: sum of (mean + w max) of Algorithm 1 (m).
  double nearest_score_m(double max_weight) const;
};

class TrialEvaluator {
 public:
  static constexpr double kMaterialStepRatio = 1.5;
  static constexpr int kMaxMaterialSteps = 24;
  // A continued simulation whose misfit S exceeds this multiple of its start's is checked
  // against a fresh one (the better is kept): continuation can carry a fold onto a wrong branch.
  static constexpr double kBranchCheckRatio = 4.0;

  // Builds the twin of the trial's sheet, meshed as `twin_mesh` says (or with about
  // `twin_triangles` triangles, unrefined). Throws std::invalid_argument when markers or clamps
  // are off the sheet or the material is invalid.
  TrialEvaluator(Trial trial, const TwinMeshSpec& twin_mesh, const Material& material);
  TrialEvaluator(Trial trial, int twin_triangles, const Material& material)
      : TrialEvaluator(std::move(trial), TwinMeshSpec{twin_triangles, {}}, material) {}
  ~TrialEvaluator();
  TrialEvaluator(const TrialEvaluator&) = delete;
  TrialEvaluator& operator=(const TrialEvaluator&) = delete;

  const Trial& trial() const { return trial_; }
  const ShellModel& model() const { return *model_; }
  // Triangles of the mesh the clamps' path is followed on in a fresh simulation of a trial
  // scanned with markers (the twin's own when no coarser one is used).
  int path_mesh_triangles() const {
    return path_model_ ? path_model_->mesh().triangle_count() : model_->mesh().triangle_count();
  }

  // Simulates every stage with `material` and scores it. The surface density is the trial's
  // (given, or mass / area) unless it is one of the varied parameters. `parameters` are the varied ones
  // (for the warm-start cache and the derivatives). Never throws for numerical trouble: a
  // stage that does not converge, or a Hessian that is not positive definite where derivatives
  // were asked for, makes the fit unusable with the reason in `failure`.
  // fresh: simulate from flat and from the scans even if an equilibrium could be continued
  // (the result joins the others; of two for the same material the better fit is continued,
  // and a fresh one that fits better replaces all earlier equilibria).
  TrialFit evaluate(const Material& material, const std::vector<MaterialParameter>& parameters,
                    Derivatives derivatives = Derivatives::kNone, bool fresh = false);

  // Forgets the equilibria of earlier evaluations: the next one starts from the flat sheet.
  void clear_warm_starts() { cache_.clear(); }

 private:
  struct CachedEquilibria {
    VecX coordinates;
    double sum_squares_m2 = 0.0;  // their misfit: of equally near entries, the better fit starts
    std::vector<VecX> stage_x;
  };
  ContinuationStarts continuation_cached(const VecX& coordinates) const;
  bool simulate_warm(const CachedEquilibria& start, const Material& target,
                     const std::vector<MaterialParameter>& parameters, TrialFit& fit);
  bool simulate_cold(TrialFit& fit, bool coarse_path_allowed = true);
  void score(TrialFit& fit) const;
  void differentiate(TrialFit& fit, const std::vector<MaterialParameter>& parameters,
                     Derivatives derivatives);
  std::vector<ClampPose> stage_poses(int stage) const;
  std::unique_ptr<ShellModel> build_model(SheetMesh mesh, const Material& material) const;
  // The model lane `lane` of a fresh simulation solves on (lane 0: model_), with model_'s material.
  ShellModel& lane_model(int lane);
  // The coarse path's model and its map onto the twin's vertices; null when the path runs on
  // the twin itself.
  void build_path_model(const TwinMeshSpec& spec);

  Trial trial_;
  std::unique_ptr<ShellModel> model_;
  std::unique_ptr<ShellModel> second_lane_model_;  // built at the first fresh simulation on two lanes
  std::unique_ptr<ShellModel> path_model_;          // coarse mesh the clamps' path is followed on
  std::unique_ptr<ClampSet> path_clamps_;
  std::unique_ptr<MaterialPointMap> path_markers_;
  std::unique_ptr<MaterialPointMap> path_to_twin_;  // the twin's vertices on the coarse mesh
  ClampSet clamps_;
  std::unique_ptr<MaterialPointMap> markers_;
  SheetPlacement placement_;
  std::unique_ptr<StaticSolver> statics_;
  std::vector<std::unique_ptr<EquilibriumSensitivity>> sensitivities_;  // per stage, reused
  std::vector<CachedEquilibria> cache_;
  std::vector<double> ages_s_;  // per stage, since the clamps last moved (stage_age.h)
};

}  // namespace twin
