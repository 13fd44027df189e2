#pragma once
// Grasp planning with the twin: chooses where 2-4 grippers take a ply and where they hold it so
// that it hangs above the tool within the goal's sag and fold limits, by simulating candidates.
//
// 1. Candidates (grasp_candidates.h) on the coarse screening mesh, grippers assigned to points
//    (grasp_assignment.h); with a cell config, candidates an arm cannot reach are dropped before
//    simulation.
// 2. Each remaining candidate is simulated to static equilibrium (hang_evaluation.h) on the
//    screening mesh and scored.
// 3. Ranking: feasible before infeasible, then least sag, then largest bend radius.
// 4. The best `finalists` (by default every screened candidate that reached an equilibrium) are
//    simulated again on the target mesh, the cell twin's, and ranked the same way; the first is
//    the plan, its predicted_sag_m the target-mesh sag. When none is feasible the plan is the
//    least bad one with feasible = false and the reason in its note. (Ranked on the screening
//    mesh alone, sags were off by up to 5 cm and the order with them. Carrying each screened
//    equilibrium to the target mesh and solving there from it was tried: on the example goal it
//    took as long as the whole path on the target mesh, 0.3-1.5 s against 0.6-0.8 s at 1539
//    triangles, and ended up to 8 mm of sag away from it.)
// 5. With search.refine_evaluations, a feasible plan is refined locally on the target mesh
//    (grasp_refinement.h); an improvement becomes the plan.
// Deterministic for a given goal (the search seed is in the goal).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cell/grasp_planning/grasp_candidates.h"
#include "cell/grasp_planning/hang_evaluation.h"
#include "drivers/cell_hardware_config.h"
#include "twin/distributed/rank_group.h"

namespace cell {

struct CandidateResult {
  GraspCandidate candidate;
  std::vector<twin::Grasp> grasps;
  std::string unreachable;                // why an arm cannot reach it ("" when reachable)
  HangEvaluation screening;               // not run when unreachable
  std::optional<HangEvaluation> target;   // finalists only
  int screening_rank = -1;                // finalists: place in the screening order (0: first)
};

struct PlannerOptions {
  const drivers::CellHardwareConfig* cell = nullptr;  // reachability and assignment by arm
  int grippers = 0;                                   // use the goal's first N grippers (0: all)
  std::function<void(const std::string&)> progress;   // optional, one line per simulation
  // The screening and final simulations (steps 2 and 4) spread over MPI ranks: every rank calls
  // plan_grasps with the same goal and gets the same result. Null: this process alone. Steps 1,
  // 3 and 5 (candidates, ranking, the sequential refinement) run on every rank.
  twin::distributed::RankGroup* ranks = nullptr;
};

struct PlannerResult {
  twin::GraspPlan plan;
  std::vector<CandidateResult> ranked;  // every candidate, finalists first in their final order
  int candidates = 0, unreachable = 0, screened = 0, finalists = 0;
  int screening_triangles = 0, target_triangles = 0;
  // How far the screening mesh was from the target's: the largest sag difference of a finalist
  // (m), and where the target mesh's best finalist stood in the screening order (1: first).
  double largest_screening_sag_error_m = 0.0;
  int screening_rank_of_best = 0;
  int refine_evaluations = 0;           // target-mesh equilibria spent refining
  bool refined = false;                 // refinement found a better plan (ranked first)
  double refine_seconds = 0.0;
  double screening_seconds = 0.0, final_seconds = 0.0;
};

// Throws std::invalid_argument when the goal allows no candidate (e.g. insets wider than the
// ply) or names grippers missing from the cell config.
PlannerResult plan_grasps(const GraspGoal& goal, const PlannerOptions& options = {});

}  // namespace cell
