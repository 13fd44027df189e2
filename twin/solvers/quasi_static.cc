#include "twin/solvers/quasi_static.h"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

namespace twin {
namespace {

double rotation_angle(const Mat3& a, const Mat3& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

}  // namespace

std::string ContinuationReport::brief() const {
  return fmt::format("{} ({} increments, {} Newton iterations, {} factorizations, {:.1f} ms)",
                     last.usable() ? "converged" : to_string(last.status), increments,
                     newton_iterations, factorizations, 1e3 * seconds);
}

QuasiStaticSolver::QuasiStaticSolver(const ShellModel& model, const ClampSet& clamps)
    : clamps_(clamps), statics_(model) {}

ContinuationReport QuasiStaticSolver::move(const std::vector<ClampPose>& from,
                                           const std::vector<ClampPose>& to, VecX& x,
                                           const ContinuationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ContinuationReport report;
  const VecX x_entry = x;
  // Increments after the first start from an equilibrium and can use the tangent predictor.
  bool at_equilibrium = false;
  auto solve = [&](const std::vector<ClampPose>& poses, bool falls = false) {
    report.last = falls            ? statics_.settle(clamps_, poses, x, options.newton)
                  : at_equilibrium ? statics_.solve_from_equilibrium(clamps_, poses, x, options.newton)
                                   : statics_.solve(clamps_, poses, x, options.newton);
    at_equilibrium = report.last.usable();
    report.newton_iterations += report.last.iterations;
    report.factorizations += report.last.factorizations;
    if (report.last.usable()) ++report.increments;
    return report.last.usable();
  };
  auto done = [&](bool ok) {
    if (!ok) x = x_entry;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
  };

  // 1. Releases: clamps engaged before and released now let go at their current poses.
  std::vector<ClampPose> current = from;
  bool released = false;
  for (std::size_t i = 0; i < to.size(); ++i) {
    if (current[i].engaged && !to[i].engaged) {
      current[i].engaged = false;
      released = true;
    }
  }
  // The sheet falls from where it hung: settle it (static_solver.h) rather than ask Newton to
  // jump there, which stalls among the wrinkles of the fall.
  if (released && !solve(current, /*falls=*/true)) return done(false);
  // A grip or a release changes which vertices are free; the predictor needs the same set.
  at_equilibrium = false;

  // 2. Grips: a newly engaged clamp starts where its material point is now.
  for (std::size_t i = 0; i < to.size(); ++i) {
    if (to[i].engaged && !current[i].engaged) {
      current[i].engaged = true;
      current[i].position_m = clamps_[i].material_point_position(x);
      current[i].rotation = clamps_[i].material_frame(x);
    }
  }

  // 3. Travel in increments; halve the increment when a solve fails.
  double travel = 0.0, turn = 0.0;
  for (std::size_t i = 0; i < to.size(); ++i) {
    if (!to[i].engaged) continue;
    travel = std::max(travel, (to[i].position_m - current[i].position_m).norm());
    turn = std::max(turn, rotation_angle(current[i].rotation, to[i].rotation));
  }
  const std::vector<ClampPose> origin = current;
  int steps = std::max(1, static_cast<int>(std::ceil(std::max(travel / options.increment_m,
                                                              turn / options.increment_rad))));
  const int max_steps = 64 * steps;
  double done_fraction = 0.0;
  while (done_fraction < 1.0) {
    const double next = std::min(1.0, done_fraction + 1.0 / steps);
    std::vector<ClampPose> poses = to;
    for (std::size_t i = 0; i < to.size(); ++i) {
      if (to[i].engaged) poses[i] = interpolate(origin[i], to[i], next);
    }
    const VecX before = x;
    if (solve(poses)) {
      done_fraction = next;
    } else {
      x = before;            // back at the last equilibrium: the predictor applies again
      at_equilibrium = true;
      steps *= 2;
      if (steps > max_steps) return done(false);
    }
  }
  return done(true);
}

}  // namespace twin
