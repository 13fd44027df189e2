#pragma once
// Where a model-form misfit is (issue 33, item 5): when the base fit leaves more than
// kModelFormFactor times what the noise and the twin's discretisation explain (verdict.h), the
// verdict "model_form" says in which stages and in which parts of the sheet. Stages and regions
// (each trial's sheet cut into 3 x 3 boxes in material coordinates, pooled over its stages) are
// listed when their residual RMS per coordinate exceeds the same multiple of the budget, worst
// first; with none beyond it on its own, the misfit is spread thin over the whole sheet.

#include <string>
#include <vector>

#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

struct MisfitStage {
  std::string label;  // "<trial>/<stage id>"
  double rms_m = 0.0;  // per coordinate
  int samples = 0;
};

struct MisfitRegion {
  std::string trial;
  int row = 0, col = 0;  // row along v (0 at v min), col along u (0 at u min), of 3 x 3
  Vec2 min_uv_m = Vec2::Zero(), max_uv_m = Vec2::Zero();
  double rms_m = 0.0;    // per coordinate, over every stage's samples in the box
  int samples = 0;
};

struct ModelFormLocation {
  double threshold_m = 0.0;  // the RMS above which a stage or region is listed
  std::vector<MisfitStage> stages;    // beyond the threshold, worst first
  std::vector<MisfitRegion> regions;  // beyond the threshold, worst first
};

// Stages and regions of `field` whose RMS exceeds threshold_m (m per coordinate).
ModelFormLocation locate_model_form(const ResidualField& field, double threshold_m);

// One sentence: "worst in stages a (x mm), b (y mm); regions u 0.00-0.39 m, v 0.65-0.98 m of
// trial t (z mm), ..." (at most `most` of each), or that the misfit is spread thin.
std::string describe(const ModelFormLocation& location, int most = 4);

}  // namespace twin::diagnosis
