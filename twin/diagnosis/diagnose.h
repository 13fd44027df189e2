#pragma once
// The discrepancy workflow end to end (issue 6), as `twin diagnose` runs it:
//   1. base fit: identify_gradient of the paper's three parameters on the training trials;
//   2. find: the residual field of the base fit on training and held-out trials, the noise
//      sigma (given, or estimated from the training residuals: noise_estimate.h), the analysis
//      (residual_analysis.h);
//   3. name: the score test of every candidate effect at the base fit; when the base residual
//      is significant, refits of the best few;
//   4. the best branch: when a refit's material with its effect removed, continued on the
//      refit's equilibria, fits the training trials better than the base fit, that effect-free
//      fit becomes the base (diagnose.cc); then the verdict (verdict.h);
//   5. add: OUT/material_augmented.json (the base material file with the named effect);
//   6. show: OUT/verdict.json, OUT/report.md with figures, and the terminal summary.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "twin/trials/discretisation_check.h"
#include "twin/diagnosis/model_form.h"
#include "twin/diagnosis/refit.h"
#include "twin/diagnosis/verdict.h"

namespace twin::distributed {
class RankGroup;
}

namespace twin::diagnosis {

struct DiagnoseOptions {
  std::vector<std::string> train, test;  // trial directories
  std::string report;                    // output directory
  std::string material;                  // optional start material file (fixed properties too)
  int triangles = 300;                   // twin mesh: coarse by default (many fits; the blind sets use it)
  // Refinement near the clamps (trial.h: TwinMeshSpec). None by default: the blind-set figures
  // were measured on uniform meshes.
  std::vector<double> clamp_refinement_radii_m;
  bool resolve_jaws = false;  // TwinMeshSpec::resolve_jaws (then no radii)
  int path_triangles = TwinMeshSpec{}.path_triangles;  // TwinMeshSpec::path_triangles
  double noise_mm = 0.0;                 // per-coordinate sigma (mm); 0: estimate it
  std::string effects;                   // comma-separated candidate names; "" = all
  int refits = 3;                        // candidates refitted, best score first
  int base_evaluations = 80;             // budget of the base fit
  int refit_evaluations = RefitOptions{}.max_evaluations;  // budget of each start of a refit
  GradientOptimizer optimizer = kDiagnosisOptimizer;  // of the base fit and every refit
  bool discretisation_check = true;      // the base fit also on a twin of twice the triangles
  std::function<void(const std::string&)> progress;  // progress lines (none when empty)
  // The ranks of an MPI run the diagnosis runs on, every rank alike (null: this process alone):
  // the refits' searches are spread over them (diagnose.cc), and rank 0 alone writes the files.
  // The outcome is the same on every rank and the same as this process alone would reach.
  distributed::RankGroup* ranks = nullptr;
};

struct DiagnoseOutcome {
  Verdict verdict;
  double sigma_m = 0.0;
  bool sigma_estimated = false;
  double sigma_relative_error = 0.0;  // when estimated: its sampling error (noise_estimate.h)
  std::string sigma_source;    // when estimated: the fit whose training residuals gave it
  double noise_floor_m = 0.0;  // expected correspondence error mean under noise alone
  // The twin's discretisation error at the base fit (discretisation_check.h): with the noise, the
  // budget the verdict judges against (verdict.h). model_form_misfit: the verdict is "model_form",
  // and model_form says where.
  DiscretisationCheck discretisation;
  bool model_form_misfit = false;
  std::optional<ModelFormLocation> model_form;
  SetScore base_train, base_test;
  // With the named effect (verdict "effect"), or the closest candidate ("unexplained"):
  std::vector<ParameterEstimate> parameters;  // every fitted parameter, 95 % intervals
  std::optional<SetScore> after_train, after_test;
  // The material as characterised: with the named effect (verdict "effect", as in
  // material_augmented.json), else the base fit's.
  Material material;
  std::string summary_text;    // the terminal summary
};

// Throws std::invalid_argument / std::runtime_error for bad input (naming the file and field).
DiagnoseOutcome run_diagnosis(const DiagnoseOptions& options);

// Mean of |e| for e with independent N(0, sigma^2) coordinates in 3D: sigma sqrt(8 / pi). The
// correspondence error a perfect model would leave (the "noise floor" of verdict.json).
double noise_floor_mean_m(double sigma_m);

}  // namespace twin::diagnosis
