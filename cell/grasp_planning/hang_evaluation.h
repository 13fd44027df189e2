#pragma once
// One candidate grasp set, simulated: the ply laid out flat and level at the hold height (turned
// and shifted so its grasp points best fit their hold positions, as the world loads it), gripped
// at its material points, then the grippers travel to their hold positions by quasi-static
// continuation and the ply settles to static equilibrium under gravity. The result is measured
// (hang_metrics.h) and judged against the goal.
#include <string>
#include <vector>

#include "cell/grasp_planning/hang_metrics.h"
#include "twin/trials/grasp_plan.h"
#include "twin/model/shell_model.h"

namespace cell {

struct HangEvaluation {
  bool solved = false;     // an equilibrium was reached
  bool feasible = false;   // solved and within every limit of the goal
  std::string reason;      // why not feasible ("sag 0.31 m > limit 0.25 m"), or "" when feasible
  HangMetrics metrics;
  double seconds = 0.0;
  twin::VecX x;            // the equilibrium (3n, m) when solved
};

// Never throws for numerical trouble or grasps that overlap on this mesh (both give an
// infeasible result with the reason).
HangEvaluation evaluate_hang(const twin::ShellModel& model, const std::vector<twin::Grasp>& grasps,
                             const GraspGoal& goal);

// The same for a whole plan (its grasps), e.g. one read from a file.
inline HangEvaluation evaluate_plan(const twin::ShellModel& model, const twin::GraspPlan& plan,
                                    const GraspGoal& goal) {
  return evaluate_hang(model, plan.grasps, goal);
}

}  // namespace cell
