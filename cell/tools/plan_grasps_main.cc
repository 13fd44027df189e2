// plan_grasps: chooses grasp locations for a ply by simulating candidates with the twin
// (cell/grasp_planning/grasp_planner.h) and writes the grasp plan file the cell executes.
//   plan_grasps --goal GOAL.json --out PLAN.json [--cell CELL.json] [--grippers N] [--seed S]
//               [--rows N] [--shape SHAPE.ply] [--threads N] [--verbose]
//   plan_grasps --goal GOAL.json --score PLAN.json [--cell CELL.json]
// Under `mpirun -np N` the candidates' simulations are spread over the N ranks
// (grasp_planner.h: PlannerOptions::ranks); rank 0 prints and writes, the plan is the same.
// --score simulates an existing plan (e.g. a hand-made one) on the goal's target mesh and prints
// its sag and fold metrics by the planner's measure, without planning.
// Prints the best candidates (material points, sag, fold metrics, feasible), how many were
// simulated and how long it took. An infeasible goal still writes the least bad plan, with
// feasible = false and the reason in its note. --shape writes the plan's predicted equilibrium.
// Exit code: 0 feasible plan written, 1 bad input or unwritable output, 2 infeasible plan written.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <exception>
#include <memory>
#include <optional>

#include <omp.h>

#include "cell/grasp_planning/grasp_assignment.h"
#include "cell/grasp_planning/grasp_planner.h"
#include "cell/grasp_planning/plan_table.h"
#include "twin/distributed/rank_group.h"
#include "twin/mesh/mesh_io.h"

namespace {

// Exit code as for planning: 0 feasible, 2 not.
int score_plan(const cell::GraspGoal& goal, const std::string& path, const drivers::CellHardwareConfig* cell) {
  const twin::GraspPlan plan = twin::read_grasp_plan(path);
  const twin::ShellModel model(goal.sheet.mesh, goal.material);
  const cell::HangEvaluation e = cell::evaluate_plan(model, plan, goal);
  const std::string unreachable = cell ? cell::check_reachability(plan.grasps, *cell) : std::string();
  if (!e.solved) {
    fmt::print("{}: no equilibrium on {} triangles: {}\n", path, model.mesh().triangle_count(), e.reason);
    return 2;
  }
  fmt::print("{}: sag {:.3f} m (limit {:.3f} m), clearance {:.3f} m, min bend radius {:.3f} m, {:.1f} % turned over, "
             "{} triangles, {:.1f} s: {}{}\n",
             path, e.metrics.sag_m, goal.max_sag_m, e.metrics.clearance_m, e.metrics.min_bend_radius_m,
             100.0 * e.metrics.overturned_fraction, model.mesh().triangle_count(), e.seconds,
             e.feasible ? "feasible" : "infeasible: " + e.reason, unreachable.empty() ? "" : "; " + unreachable);
  return e.feasible && unreachable.empty() ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Grasp planning with the twin: writes a grasp plan file"};
  std::string goal_path, out_path, cell_path, shape_path, score_path;
  int grippers = 0, rows = 10, threads = 1;
  std::optional<unsigned> seed;
  bool verbose = false;
  app.add_option("--goal", goal_path, "goal file (JSON)")->required()->check(CLI::ExistingFile);
  auto* out = app.add_option("--out", out_path, "grasp plan file to write (JSON)");
  auto* score = app.add_option("--score", score_path, "score this plan instead of planning")->check(CLI::ExistingFile);
  out->excludes(score);
  app.add_option("--cell", cell_path, "cell config: assign grippers by arm and check reachability")
      ->check(CLI::ExistingFile);
  app.add_option("--grippers", grippers, "use the goal's first N grippers (2-4)")->check(CLI::Range(2, 4));
  app.add_option("--seed", seed, "random candidate seed (overrides the goal's search.seed)");
  app.add_option("--rows", rows, "candidates to print")->check(CLI::PositiveNumber);
  app.add_option("--shape", shape_path, "write the plan's predicted hanging shape (PLY or OBJ)");
  // One thread by default: screening meshes are small and candidates are solved one after the
  // other, so a second thread mostly waits (measured: 2 threads were slower on a loaded 2-core box).
  app.add_option("--threads", threads, "worker threads of the twin's element loops")->check(CLI::PositiveNumber);
  app.add_flag("--verbose", verbose, "print every simulation");
  CLI11_PARSE(app, argc, argv);
  if (out_path.empty() && score_path.empty()) {
    fmt::print(stderr, "plan_grasps: --out PLAN.json (or --score PLAN.json) is required\n");
    return 1;
  }

  omp_set_num_threads(threads);
  try {
    // Before anything can fail, so that every rank meets the same error; MPI finishes last.
    const std::unique_ptr<twin::distributed::RankGroup> ranks = twin::distributed::join_ranks();
    const bool reporter = ranks->rank() == 0;
    cell::GraspGoal goal = cell::read_grasp_goal(goal_path);
    if (seed) goal.search.seed = *seed;
    std::optional<drivers::CellHardwareConfig> cell;
    if (!cell_path.empty()) cell = drivers::read_cell_hardware(cell_path);
    if (!score_path.empty()) return reporter ? score_plan(goal, score_path, cell ? &*cell : nullptr) : 0;
    cell::PlannerOptions options;
    options.cell = cell ? &*cell : nullptr;
    options.grippers = grippers;
    options.ranks = ranks.get();
    const std::string prefix = ranks->size() > 1 ? fmt::format("[rank {}/{}] ", ranks->rank(), ranks->size()) : "";
    if (verbose) options.progress = [prefix](const std::string& line) { fmt::print("{}{}\n", prefix, line); };
    const cell::PlannerResult r = cell::plan_grasps(goal, options);
    if (!reporter) return 0;  // rank 0 reports for all
    fmt::print("{}", cell::candidate_table(r, rows));
    fmt::print("{} candidates, {} unreachable, {} simulated on {} triangles in {:.1f} s, {} on {} triangles in {:.1f} s, "
               "refinement {} on {} triangles in {:.1f} s ({})\n",
               r.candidates, r.unreachable, r.screened, r.screening_triangles, r.screening_seconds, r.finalists,
               r.target_triangles, r.final_seconds, r.refine_evaluations, r.target_triangles, r.refine_seconds,
               r.refined ? "improved" : "no improvement");
    if (r.finalists > 0) {
      fmt::print("screening mesh vs target mesh: sags differ by up to {:.3f} m; the target's best stood {} of {} "
                 "in the screening order\n",
                 r.largest_screening_sag_error_m, r.screening_rank_of_best, r.finalists);
    }
    twin::write_grasp_plan(r.plan, out_path);
    fmt::print("{}: {}\n", out_path, r.plan.note);
    if (!shape_path.empty()) {
      const cell::CandidateResult& best = r.ranked.front();
      const cell::HangEvaluation* e = best.target ? &*best.target : nullptr;
      if (e && e->solved) {
        twin::write_surface_mesh(shape_path, twin::surface_from_positions(goal.sheet.mesh, e->x));
      } else {
        fmt::print(stderr, "no predicted shape to write to {}\n", shape_path);
      }
    }
    return r.plan.feasible ? 0 : 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "plan_grasps: {}\n", e.what());
    return 1;
  }
}
