#pragma once
// Per-marker residuals of a fitted trial, for looking at where the twin misses (docs/file_formats.md,
// "Residual files"). Per stage:
//   <stage>_residuals.csv   one row per marker (or cloud point): index, u_m, v_m (material
//                           point; empty for cloud points), observed x y z, predicted x y z,
//                           residual x y z (predicted - observed), correspondence_m,
//                           nearest_vertex_m (Algorithm 1); NaN where the marker was not seen.
//   <stage>_residuals.ply   the seen markers as points at their observed positions, with the
//                           residual vector (rx, ry, rz) and its length (error_m) as properties.
//   <stage>_predicted.ply   the twin's sheet at that stage.
// Files are written atomically; the directory is created if needed.

#include <string>

#include "twin/trials/trial_evaluator.h"

namespace twin {

void write_residual_files(const std::string& directory, const TrialEvaluator& evaluator, const TrialFit& fit);

}  // namespace twin
