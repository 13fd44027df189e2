#pragma once
// The planner's candidates as a text table, best first: material points, sag, fold metrics,
// feasibility and the mesh they were scored on (what plan_grasps prints).
#include <string>

#include "cell/grasp_planning/grasp_planner.h"

namespace cell {

std::string candidate_table(const PlannerResult& result, int rows);

}  // namespace cell
