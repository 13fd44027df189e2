#pragma once
// Material identification from scanned trials (paper section 4.3), two ways:
//   - the paper's: screen 27 candidate materials, bound the search around the best, and run
//     NLopt's GN_ISRES (gradient-free, seeded) on Eq. 11, the sum over training stages of the
//     Algorithm 1 error mean + w max (w = 2);
//   - ours: least squares on the markers (trial_evaluator.h), with the gradient from one adjoint
//     solve per stage, driving NLopt's LD_LBFGS in search coordinates (log p, or p / scale for
//     effect parameters that may be zero: material_parameters.h); then the Gauss-Newton
//     (Fisher) covariance at the optimum gives 95 % intervals, and a parameter the data do not
//     pin down is reported as not determined instead of as a number.
// Both search in log space (stiffnesses span decades; a relative step means the same
// everywhere) and vary only the chosen parameters; everything else (density from the trial's
// mass, Poisson ratio, thickness) stays as in the base material.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "twin/trials/trial_evaluator.h"

namespace twin {

class IdentificationProblem {
 public:
  // The evaluators are borrowed (one per training trial) and must outlive the problem.
  IdentificationProblem(std::vector<TrialEvaluator*> training, Material base,
                        std::vector<MaterialParameter> parameters);

  const std::vector<MaterialParameter>& parameters() const { return parameters_; }
  const Material& base() const { return base_; }
  Material material_at(const VecX& coordinates) const;
  VecX coordinates_of(const Material& material) const;

  struct Evaluation {
    std::string failure;                 // empty when every training trial simulated
    bool usable() const { return failure.empty(); }
    std::vector<TrialFit> fits;          // one per training trial
    double nearest_score_m = 0.0;        // sum over stages of Algorithm 1 mean + w max (m)
    double mean_square_m2 = 0.0;         // sum of squared residuals / their count (m^2)
    int residual_count = 0;
    VecX coordinate_gradient;                   // d mean_square / d y (m^2), y the search coordinates
    Eigen::MatrixXd coordinate_jacobian;        // stacked over trials, when asked (m)
    VecX residuals_m;                    // stacked like the Jacobian
    std::vector<int> residual_blocks;    // per residual: trial * 1000 + TrialFit::residual_blocks
    double seconds = 0.0;
  };
  // fresh: see TrialEvaluator::evaluate.
  Evaluation evaluate(const VecX& coordinates, Derivatives derivatives, double max_weight, bool fresh = false);

  // The next evaluation simulates every trial from flat and from its scans again (see
  // trial_evaluator.h), instead of continuing the equilibria of earlier materials.
  void forget_warm_starts();

  // Per training trial and per stage, the weight of the stage's squared residuals in the
  // objective (empty: every weight 1). A robust refit (diagnosis/stage_weights.h) lowers the
  // weight of a stage that sits on another fold, so that one stage cannot pull the fit off the
  // material every other stage agrees on. With weights, residuals_m and the Jacobian's rows
  // are scaled by sqrt(w), mean_square_m2 is sum w r^2 / sum w, and only Derivatives::kNone
  // and kJacobian are available (the adjoint gradient is not split by stage): kGradient
  // throws std::logic_error.
  void set_stage_weights(std::vector<std::vector<double>> weights);
  const std::vector<std::vector<double>>& stage_weights() const { return stage_weights_; }

  // Trial simulations run so far (one per training trial per evaluation).
  int simulations() const { return simulations_; }
  // Called after every evaluation (progress output).
  std::function<void(const VecX& coordinates, const Evaluation&)> on_evaluation;

 private:
  std::vector<TrialEvaluator*> training_;
  Material base_;
  std::vector<MaterialParameter> parameters_;
  std::vector<std::vector<double>> stage_weights_;
  int simulations_ = 0;
  double stage_weight(std::size_t trial, int stage) const;
};

struct ParameterEstimate {
  MaterialParameter parameter{};
  double value = 0.0;                    // SI units (parameter_name says which)
  double lower95 = 0.0, upper95 = 0.0;   // 95 % interval (see estimate_uncertainty)
  bool block_robust = false;             // the interval is the cluster-robust one (wider)
  bool determined = false;               // interval narrower than a factor kDeterminedRatio
  // The search stopped at the edge of its range: the data pushed it there and would have gone
  // further, so the interval reaches the parameter's physical bound on that side and the
  // parameter is not determined, however narrow the curvature of the misfit makes it look.
  bool at_search_edge = false;
  // What the twin's own discretisation error (the part the residual holds,
  // discretisation_check.h) moves the estimate by, to first order (SI units, signed): the
  // Gauss-Newton step of the fit with that error taken out. A systematic error the Fisher or
  // sandwich interval does not see; the interval is widened by it on both sides. 0 when not
  // given.
  double discretisation_shift = 0.0;
  static constexpr double kDeterminedRatio = 2.0;  // upper95 / value and value / lower95 below it
};

struct IdentificationResult {
  std::string method;
  Material material;                     // base with the identified parameters
  VecX coordinates;
  VecX start_coordinates;                 // where the search started (the best screening candidate)
  double objective = 0.0;                // the method's own objective at the result
  std::string objective_name;
  int evaluations = 0, simulations = 0;  // simulations: whole-trial simulations, screening included
  double seconds = 0.0;
  std::string stop_reason;
  std::vector<ParameterEstimate> estimates;  // filled by estimate_uncertainty
  std::vector<char> at_search_edge;          // per parameter, set by the gradient search
  double noise_sigma_m = 0.0;            // residual RMS per coordinate at the result
};

// --- the paper's method -------------------------------------------------------------------

struct IsresOptions {
  unsigned seed = 1;
  int max_evaluations = 600;       // after screening
  double max_weight = 2.0;         // Eq. 11
  // Bounds around the best screening candidate, as the paper set them (its Sec. 4.3.2: best
  // {5000, 5000, 0.001} -> [1000, 9000] for the stiffnesses and [0.0009, 0.0011] for bending).
  double stiffness_lower = 0.2, stiffness_upper = 1.8;
  double bending_lower = 0.9, bending_upper = 1.1;
};

// The 27 screening candidates of the paper: {500, 5000, 50000} N/m for tensile and shear,
// {0.01, 0.001, 0.0001} N*m for bending. Requires the parameters to be exactly
// {kTensile, kShear, kBending} (std::invalid_argument otherwise).
std::vector<VecX> paper_screening_candidates(const IdentificationProblem& problem);

// The default start of an identification when the user gives no material: the paper's middle
// screening candidate (5000 N/m, 5000 N/m, 0.001 N*m) with Poisson 0.3 and the trial's
// thickness and material name.
Material paper_middle_candidate(const Trial& trial);

IdentificationResult identify_isres(IdentificationProblem& problem, const IsresOptions& options);

// --- gradients ----------------------------------------------------------------------------

enum class GradientOptimizer {
  // Levenberg-Marquardt on the marker residuals, Jacobian from the equilibria's tangents
  // (levenberg_marquardt.h): a handful of evaluations where the data leave a flat valley.
  kLevenbergMarquardt,
  // NLopt LD_LBFGS on the mean square, gradient by one adjoint solve per stage.
  kLbfgs,
};

// The optimiser's name on command lines and in output files: "lm" or "lbfgs".
const char* optimizer_name(GradientOptimizer optimizer);
// The optimiser of a name from optimizer_name (anything else: invalid_argument naming it).
GradientOptimizer optimizer_from_name(const std::string& name);

struct GradientOptions {
  GradientOptimizer optimizer = GradientOptimizer::kLevenbergMarquardt;
  std::optional<VecX> start_coordinates;  // default: log of the base material's values
  int max_evaluations = 80;
  // The search stays within this factor of the start in every parameter (and within sane
  // physical bounds). L-BFGS's first line searches otherwise try materials thousands of times
  // off, whose simulations fail slowly. A result at this bound is reported in stop_reason.
  double search_ratio = 20.0;
  // The same for linear (effect) parameters: within this many units of their scale of the start.
  double linear_search_span = 10.0;
  double x_tolerance = 5e-3;             // in y: for log p a relative change of 0.5 % ends the search
  double f_tolerance = 1e-5;             // relative change of the objective
  // After L-BFGS converges, the trials are re-simulated from scratch at the result: continuing
  // equilibria through large material changes can leave a fold on a branch that the result's
  // material would not choose. If that lowers the objective by more than restart_gain
  // (relative), L-BFGS runs again from there; at most max_restarts times.
  int max_restarts = 3;
  double restart_gain = 0.01;
};

IdentificationResult identify_gradient(IdentificationProblem& problem, const GradientOptions& options);

// 95 % intervals in log space at the result; fills result.estimates and result.noise_sigma_m.
// One more evaluation (with tangents), counted in result.simulations. Two covariances:
//  - Gauss-Newton (Fisher) sigma^2 (J^T J)^-1, sigma^2 the residual variance: right when the
//    residuals are independent noise;
//  - cluster-robust (sandwich) (J^T J)^-1 [sum_b J_b^T r_b r_b^T J_b] (J^T J)^-1 * B/(B-1), over
//    the blocks b of residuals of one stage and one quarter of the sheet (B of them): the twin's
//    own model error is smooth across the sheet, so its residuals come correlated in such
//    blocks, and the Fisher intervals are then too narrow.
// With kFisherOrBlocks each parameter's interval uses the larger of its two variances
// (ParameterEstimate::block_robust says when that is the sandwich's); kFisher is the Fisher
// interval alone, which the diagnosis's significance tests were measured with.
enum class IntervalKind { kFisher, kFisherOrBlocks };
// With `discretisation_error_m` (the twin's discretisation error the residual holds, stacked like
// the problem's residuals: DiscretisationCheck::error_pattern_m times pattern_in_residual), each
// interval is also widened on both sides by the shift that error makes (discretisation_shift):
// half width 1.96 sd + |shift| in the search coordinate. A vector of another length is ignored.
void estimate_uncertainty(IdentificationProblem& problem, IdentificationResult& result,
                          IntervalKind kind = IntervalKind::kFisher, const VecX* discretisation_error_m = nullptr);

}  // namespace twin
