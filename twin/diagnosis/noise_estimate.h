#pragma once
// The measurement noise sigma (m, per coordinate) estimated from a residual field itself, for
// when the user does not give it. The residual is noise plus model error; model error is smooth
// over the sheet, noise is independent from marker to marker. So the estimator works on local
// differences that cancel a locally smooth field:
//  - markers on a grid: third differences along rows and columns (cancel a locally quadratic
//    field), d = -r(c) + 3 r(c+1) - 3 r(c+2) + r(c+3),  Var d = 20 sigma^2 for independent noise;
//  - other markers: each marker against the plane fitted to the residuals of its nearest
//    neighbours on the material, d = r_i - plane(uv_i),  Var d = sigma^2 (1 + h_i), h_i the
//    plane's leverage at uv_i.
// Every coordinate of every stage contributes. The same differences are taken of the observed
// marker positions too: a real sheet is smooth at the marker spacing, while the twin's
// prediction is piecewise linear over its (coarse) mesh, whose kinks leak into the residual's
// differences when the model error is large. Each of the two is only biased upward (by what
// does not cancel), so the smaller is taken; for pure noise they agree within a few percent
// (the minimum is ~1 % low). LIMIT, measured on lab trials (sigma 0.3 mm, 300-triangle twin):
// model error RMS 3.5 mm (twice the bending) -> 0.35 mm; model error RMS 10 mm (a 1200-triangle
// lab reference, itself kinked at its edges) -> 0.91 mm from the residuals, 0.73 mm from the
// observations. With a large model error, give the noise level.
// The scale is taken robustly (the median of d^2 / variance factor, divided by the median of
// chi-square with one dof, 0.4549), so a few markers with sharp model error (next to a clamp,
// say) do not inflate it.

#include <string>

#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

struct NoiseEstimate {
  double sigma_m = 0.0;         // per-coordinate standard deviation (m): the smaller of
  double from_residuals_m = 0.0;     // the estimate from the residuals' differences and
  double from_observations_m = 0.0;  // from the observed markers' (+inf when too few)
  int differences_used = 0;     // scalar differences the estimate rests on
  std::string method;           // "grid third differences" / "neighbour planes" (or both), "of the
                                // residuals" / "of the observed markers"
};

// Throws std::invalid_argument when the field has too few markers per stage to difference
// (fewer than 16 scalar differences in all).
NoiseEstimate estimate_noise(const ResidualField& field);

}  // namespace twin::diagnosis
