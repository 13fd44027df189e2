#pragma once
// The measurement noise sigma (m, per coordinate) estimated from a residual field itself, for
// when the user does not give it. The residual is noise plus model error; model error is smooth
// over the sheet, noise is independent from marker to marker. So the estimator works on local
// differences that cancel a locally linear field:
//  - markers on a grid: second differences along rows and columns,
//      d = r(c-1) - 2 r(c) + r(c+1),  Var d = 6 sigma^2 for independent noise;
//  - other markers: each marker against the plane fitted to the residuals of its nearest
//    neighbours on the material, d = r_i - plane(uv_i),  Var d = sigma^2 (1 + h_i), h_i the
//    plane's leverage at uv_i.
// Every coordinate of every stage contributes. The scale is taken robustly (the median of
// d^2 / variance factor, divided by the median of chi-square with one dof, 0.4549), so a few
// markers with sharp model error (next to a clamp, say) do not inflate it.

#include <string>

#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

struct NoiseEstimate {
  double sigma_m = 0.0;         // per-coordinate standard deviation (m)
  int differences_used = 0;     // scalar differences the estimate rests on
  std::string method;           // "grid second differences", "neighbour planes" or both
};

// Throws std::invalid_argument when the field has too few markers per stage to difference
// (fewer than 16 scalar differences in all).
NoiseEstimate estimate_noise(const ResidualField& field);

}  // namespace twin::diagnosis
