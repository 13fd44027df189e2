#pragma once
// The structure half of the residual analysis (residual_analysis.h describes the measures):
// does the residual vary along u or along v, and does its size follow the distance from the
// clamps, the curvature, the stage load or the stage age.

#include <vector>

#include "twin/diagnosis/residual_analysis.h"

namespace twin::diagnosis {

DirectionStructure analyse_direction(const ResidualField& field, double sigma_m, double alpha);

std::vector<Correlation> analyse_correlations(const ResidualField& field, double alpha);

}  // namespace twin::diagnosis
