#pragma once
// The twin's discretisation error at the resolution in use, measured where it matters: the
// predicted markers of trials, simulated with the same material on the twin's mesh and on one of
// twice the triangles. To first order that change is the error of the coarser twin, a part of
// every residual beside the scanner noise that no material and no effect can remove
// (identification and diagnosis report it; issue 33's error budget).

#include <string>
#include <vector>

#include "twin/model/material.h"
#include "twin/model/material_parameters.h"
#include "twin/trials/trial_evaluator.h"

namespace twin {

struct DiscretisationCheck {
  std::string failure;  // empty when both resolutions simulated every trial
  bool usable() const { return failure.empty(); }
  double rms_m = 0.0;   // markers' change per coordinate, RMS over markers and stages
  double max_m = 0.0;   // largest change of one marker
  int triangles = 0, finer_triangles = 0;
  double finer_residual_rms_m = 0.0;  // the material's residual per coordinate on the finer twin
  // The twin's error pattern: its residual vector minus the finer twin's (what the finer twin
  // removes), stacked over the trials like an IdentificationProblem's residuals; empty when the
  // two stack differently (a stage seen by a cloud). What a candidate effect could absorb of it
  // is its projection onto the effect's span (score_test.h).
  VecX error_pattern_m;
  // How much of that pattern the twin's residual holds: the least-squares coefficient alpha of
  // the pattern in the residual (1 when the residual holds it as measured; about 1 / (1 - 2^(-p/2))
  // when the twin converges at order p, since twice the triangles remove only part of the error;
  // near 0 when the data were made on this very mesh), and the RMS per coordinate of alpha (at
  // least 0) times the pattern: the discretisation error the residual holds. It can never
  // exceed the residual's RMS, which is what keeps a twin scored on its own mesh honest too.
  double pattern_in_residual = 0.0;
  double error_in_residual_rms_m = 0.0;
};

// `trials` are evaluated with `material` (their own meshes) and read again onto a twin of twice
// `mesh.triangles`. `parameters` is the list the evaluators were used with (warm starts).
DiscretisationCheck check_discretisation(const std::vector<TrialEvaluator*>& trials, const TwinMeshSpec& mesh,
                                         const Material& material,
                                         const std::vector<MaterialParameter>& parameters);

// One line for a report: "markers move ... from N to 2N triangles <where>; residual ...".
std::string describe(const DiscretisationCheck& check, const std::string& where);

}  // namespace twin
