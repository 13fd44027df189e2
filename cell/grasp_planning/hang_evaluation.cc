#include "cell/grasp_planning/hang_evaluation.h"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/solvers/quasi_static.h"
#include "twin/trials/trial_simulation.h"

namespace cell {
namespace {

void judge(const GraspGoal& goal, HangEvaluation& e) {
  const HangMetrics& m = e.metrics;
  std::string why;
  auto add = [&why](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
  if (m.sag_m > goal.max_sag_m) add(fmt::format("sag {:.3f} m > limit {:.3f} m", m.sag_m, goal.max_sag_m));
  if (m.clearance_m < goal.min_clearance_m) {
    add(fmt::format("clearance over the tool {:.3f} m < {:.3f} m", m.clearance_m, goal.min_clearance_m));
  }
  if (m.min_bend_radius_m < goal.folds.min_bend_radius_m) {
    add(fmt::format("fold: bend radius {:.3f} m < {:.3f} m", m.min_bend_radius_m,
                    goal.folds.min_bend_radius_m));
  }
  if (m.overturned_fraction > goal.folds.max_overturned_fraction) {
    add(fmt::format("fold: {:.1f} % of the ply turned over > {:.1f} %", 100.0 * m.overturned_fraction,
                    100.0 * goal.folds.max_overturned_fraction));
  }
  e.feasible = why.empty();
  e.reason = why;
}

}  // namespace

HangEvaluation evaluate_hang(const twin::ShellModel& model, const std::vector<twin::Grasp>& grasps,
                             const GraspGoal& goal) {
  const auto start = std::chrono::steady_clock::now();
  HangEvaluation e;
  std::vector<twin::ClampSpec> specs;
  std::vector<twin::ClampPose> target;
  for (const twin::Grasp& g : grasps) {
    specs.push_back(g.clamp);
    specs.back().id = g.gripper;
    twin::ClampPose p;
    p.position_m = g.hold_position_m;
    target.push_back(p);
  }
  try {
    const twin::ClampSet clamps(model.mesh(), specs);
    const twin::SheetPlacement placement = twin::fit_level_placement(specs, target);
    // The jaws close on the level ply and travel without turning.
    for (twin::ClampPose& p : target) p.rotation = placement.rotation;
    std::vector<twin::ClampPose> open(specs.size());
    for (twin::ClampPose& p : open) p.engaged = false;
    twin::VecX x = twin::place_flat(model.mesh(), placement);
    twin::QuasiStaticSolver solver(model, clamps);
    twin::ContinuationOptions options;
    options.increment_m = 0.03;
    const twin::ContinuationReport report = solver.move(open, target, x, options);
    if (!report.usable()) {
      e.reason = "no equilibrium: " + report.brief();
    } else {
      e.solved = true;
      e.x = x;
      e.metrics = measure_hang(model.mesh(), x, goal.hold_z_m, goal.tool);
      judge(goal, e);
    }
  } catch (const std::invalid_argument& error) {
    // Grasp points off the ply or two grasps gripping the same vertices of this mesh.
    e.reason = error.what();
  }
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return e;
}

}  // namespace cell
