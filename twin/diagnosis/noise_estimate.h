#pragma once
// The measurement noise sigma (m, per coordinate) estimated from a residual field itself, for
// when the user does not give it.
//
// When the trials scan a pose more than once (stages one after another with the clamps
// untouched: FieldStage::pose_group), the noise is read from the scans' differences: the sheet's
// shape, folds and all, is the same in both and cancels; what the sheet did between them
// (relaxation) is smooth over the sheet and the local fit below cancels it. Nothing of the model
// enters. LIMIT: this is the scanner's repeatability. An error that repeats identically from scan
// to scan (a marker glued off its nominal material point, a marker-centre bias) is not in it and
// shows as model error; when the markers' placement is uncertain, give the noise level.
//
// Without repeated scans: the residual is noise plus model error; model error is smooth over the
// sheet, noise is independent from marker to marker. So the estimator compares each
// marker with a local quartic in (u, v) fitted to its 24 nearest markers (on a grid, the 5 x 5
// block around it), d = r - p(uv), Var d = sigma^2 (1 + h), h the fit's variance factor at the
// marker; it cancels a locally quartic field, and it is the same whether the markers come as a
// grid or as a list.
// Every coordinate of every stage contributes. The same differences are taken of the observed
// marker positions too: a real sheet is smooth at the marker spacing, while the twin's
// prediction is piecewise linear over its (coarse) mesh, whose kinks leak into the residual's
// differences when the model error is large. Each of the two is only biased upward (by what
// does not cancel), so the smaller is taken. LIMIT: a sheet that folds between markers is not
// smooth at their spacing: on an independent-lab composite trial (17 x 17 markers 6-7 cm apart,
// folds of 2-5 cm radius, 0.3 mm noise) the estimate from the observed markers is 0.68 mm
// (tests/diagnosis/noise_estimate_test.cc). With such a sheet, scan a pose twice or give the
// noise level.
// The scale is taken robustly (the median of d^2 / variance factor, divided by the median of
// chi-square with one dof, 0.4549), so a few markers with sharp model error (next to a clamp,
// say) do not inflate it.

#include <string>

#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

struct NoiseEstimate {
  double sigma_m = 0.0;         // per-coordinate standard deviation (m): the repeated scans' estimate,
                                // or else the smaller of
  double from_residuals_m = 0.0;     // the estimate from the residuals' differences and
  double from_observations_m = 0.0;  // from the observed markers' (+inf when too few)
  double from_repeated_scans_m = 0.0;  // from repeated scans' differences (+inf without any);
                                       // sigma_m when finite
  int differences_used = 0;     // scalar differences the estimate rests on
  // Relative standard error of sigma_m from sampling alone: 1.166 / sqrt(differences_used), the
  // spread of a median-of-chi-square scale over independent differences (of repeated scans:
  // those of every other pair of a pose, differences_used counts all; it does not cover the
  // upward bias of model error). A residual RMS within a few of these of sigma is not evidence.
  double relative_standard_error = 0.0;
  std::string method;           // "repeated scans of one pose" / "local quartic fits of the
                                // residuals" / "... of the observed markers"
};

// Throws std::invalid_argument when the field has too few markers per stage to difference
// (fewer than 16 scalar differences in all).
NoiseEstimate estimate_noise(const ResidualField& field);

}  // namespace twin::diagnosis
