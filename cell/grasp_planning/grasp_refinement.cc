#include "cell/grasp_planning/grasp_refinement.h"

#include <algorithm>
#include <chrono>

#include <nlopt.hpp>

#include "cell/grasp_planning/grasp_assignment.h"

namespace cell {
namespace {

double objective_m(const CandidateResult& c, const GraspGoal& goal) {
  if (!c.unreachable.empty() || !c.screening.solved) return 10.0;
  const HangMetrics& m = c.screening.metrics;
  const bool other_limit = m.clearance_m < goal.min_clearance_m ||
                           m.min_bend_radius_m < goal.folds.min_bend_radius_m ||
                           m.overturned_fraction > goal.folds.max_overturned_fraction;
  return m.sag_m + (other_limit ? 1.0 : 0.0);
}

}  // namespace

RefinementResult refine_candidate(const twin::ShellModel& model, const GraspGoal& goal,
                                  const CandidateResult& start, const drivers::CellHardwareConfig* cell,
                                  int max_evaluations) {
  const auto t0 = std::chrono::steady_clock::now();
  RefinementResult r;
  r.best = start;
  r.best.target.reset();
  const double start_objective = objective_m(start, goal);
  double best_objective = start_objective;
  const std::size_t n = start.grasps.size();
  std::vector<std::string> names;
  std::vector<double> x;
  for (const twin::Grasp& g : start.grasps) {
    names.push_back(g.gripper);
    x.push_back(g.clamp.material_point_m.x());
    x.push_back(g.clamp.material_point_m.y());
  }
  // Bounds: the ply's bounding box, inset by the grip radius so the jaws stay on the ply.
  twin::Vec2 lo = model.mesh().rest_uv.front(), hi = lo;
  for (const twin::Vec2& p : model.mesh().rest_uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double margin = std::max(goal.grip_radius_m, 0.01);
  std::vector<double> lower, upper;
  for (std::size_t i = 0; i < n; ++i) {
    lower.insert(lower.end(), {lo.x() + margin, lo.y() + margin});
    upper.insert(upper.end(), {hi.x() - margin, hi.y() - margin});
  }
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], lower[i], upper[i]);

  auto evaluate = [&](const std::vector<double>& p) {
    CandidateResult c;
    c.candidate = start.candidate;
    c.candidate.kind = "refined";
    c.candidate.points_uv_m.clear();
    for (std::size_t i = 0; i < n; ++i) c.candidate.points_uv_m.emplace_back(p[2 * i], p[2 * i + 1]);
    // Points stay in gripper order: no re-assignment while refining.
    c.grasps = assign_grippers(names, c.candidate.points_uv_m, hold_positions(model.mesh(), goal, c.candidate),
                               goal.grip_radius_m, nullptr);
    if (cell) c.unreachable = check_reachability(c.grasps, *cell);
    if (c.unreachable.empty()) c.screening = evaluate_hang(model, c.grasps, goal);
    ++r.evaluations;
    const double value = objective_m(c, goal);
    if (value < best_objective) {
      best_objective = value;
      r.best = c;
    }
    return value;
  };

  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(x.size()));
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_initial_step(0.5 * goal.search.ring_spacing_m);
  opt.set_maxeval(max_evaluations);
  opt.set_xtol_abs(1e-3);  // 1 mm on the ply is far below what a gripper places
  using Evaluate = decltype(evaluate);
  opt.set_min_objective(
      [](const std::vector<double>& p, std::vector<double>&, void* data) {
        return (*static_cast<Evaluate*>(data))(p);
      },
      &evaluate);
  double value = 0.0;
  try {
    opt.optimize(x, value);
  } catch (const std::exception&) {
    // NLopt stops on round-off or a forced stop; the best point seen is kept either way.
  }
  r.improved = best_objective < start_objective;
  if (!r.improved) r.best = start;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace cell
