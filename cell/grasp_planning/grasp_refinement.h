#pragma once
// Local refinement of a candidate (the planner's best, on the target mesh): the grasps' material points move freely on
// the ply (each gripper keeps its point's role; slack and gripper assignment stay), driven by
// NLopt's BOBYQA, a derivative-free method (the equilibrium can jump between branches, so sag is
// not smooth in the points), starting from the candidate with steps of half the ring spacing.
// `start.screening` must be its evaluation on `model`. Objective: sag (m), plus 1 m when a fold or clearance limit is broken, 10 m when there is no
// equilibrium or an arm cannot reach. Deterministic; costs one equilibrium per evaluation.
#include "cell/grasp_planning/grasp_planner.h"

namespace cell {

struct RefinementResult {
  CandidateResult best;  // kind "refined" when improved; its `screening` evaluation is on `model`
  int evaluations = 0;
  double seconds = 0.0;
  bool improved = false;  // lower objective than the start
};

RefinementResult refine_candidate(const twin::ShellModel& model, const GraspGoal& goal,
                                  const CandidateResult& start, const drivers::CellHardwareConfig* cell,
                                  int max_evaluations);

}  // namespace cell
