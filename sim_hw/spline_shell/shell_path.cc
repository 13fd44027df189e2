#include "sim_hw/spline_shell/shell_path.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::spline_shell {
namespace {

// The sheet's own frame at a material point (u tangent, v completing, normal), for a jaw that
// closes on the hanging sheet.
Eigen::Matrix3d frame_at(const SplinePatch& patch, const VecX& x, const Vec2& uv) {
  const PointWeights pw = patch.weights_at(uv);
  Vec3 xu = Vec3::Zero();
  for (std::size_t k = 0; k < pw.controls.size(); ++k) xu += pw.w(kU, k) * x.segment<3>(3 * pw.controls[k]);
  const Vec3 n = patch.normal(x, uv);
  const Vec3 u = (xu - xu.dot(n) * n).normalized();
  Eigen::Matrix3d R;
  R.col(0) = u;
  R.col(1) = n.cross(u);
  R.col(2) = n;
  return R;
}

}  // namespace

std::vector<SquareJaw> clamp_jaws(const std::vector<twin::ClampSpec>& clamps, double width_m, double height_m) {
  std::vector<SquareJaw> jaws;
  for (const twin::ClampSpec& c : clamps) jaws.push_back(square_jaw(c.id, c.material_point_m, c.grip_radius_m, width_m, height_m));
  return jaws;
}

ShellPathResult follow_path(ShellModel& model, const std::vector<SquareJaw>& jaws,
                            const std::vector<real_sheet::PathStage>& stages, const ShellPathOptions& options) {
  ShellPathResult result;
  if (stages.empty()) {
    result.failure = "the trial has no stages";
    return result;
  }
  std::vector<twin::ClampSpec> specs;
  for (const SquareJaw& j : jaws) specs.push_back(twin::ClampSpec{j.id, j.material_point_m, j.half_side_m});
  const real_sheet::LevelPlacement placement = real_sheet::level_placement(specs, stages.front().poses);
  const SplinePatch& patch = model.patch();
  const std::vector<double> gu = patch.u().greville(), gv = patch.v().greville();
  VecX x(model.dof_count());
  for (int j = 0; j < patch.nv(); ++j) {
    for (int i = 0; i < patch.nu(); ++i) x.segment<3>(3 * patch.control(i, j)) = placement.to_world(Vec2(gu[i], gv[j]));
  }
  std::vector<std::optional<JawHold>> held(jaws.size());
  const auto holds = [&] {
    ShellHolds h;
    for (const auto& j : held) {
      if (j) h.jaws.push_back(*j);
    }
    return h;
  };
  const auto solve = [&](double damping) {
    ShellSolveOptions o = options.solve;
    o.initial_damping_1_s2 = damping;
    // A fall is a long overdamped motion (a released corner swings half a metre).
    if (damping > 0) o.max_iterations = std::max(o.max_iterations, 5000);
    const ShellSolveReport r = solve_shell(model, holds(), x, o);
    result.iterations += r.iterations;
    result.factorizations += r.factorizations;
    ++result.increments;
    return r;
  };

  for (std::size_t k = 0; k < stages.size(); ++k) {
    const real_sheet::PathStage& stage = stages[k];
    if (stage.poses.size() != jaws.size()) throw std::invalid_argument("spline shell: a stage must pose every clamp");
    model.set_age_s(0.0);
    bool fell = false;
    std::vector<Vec3> start(jaws.size()), target(jaws.size());
    for (std::size_t c = 0; c < jaws.size(); ++c) {
      if (!stage.poses[c].engaged) {
        fell |= held[c].has_value();
        held[c].reset();
        continue;
      }
      if (!held[c]) {
        JawHold j;
        j.jaw = jaws[c];
        j.centre_m = patch.position(x, jaws[c].material_point_m);
        j.rotation = k == 0 ? placement.rotation : frame_at(patch, x, jaws[c].material_point_m);
        held[c] = j;
        fell = true;  // the first grip lets the level sheet go; a later one snaps the pad flat
      }
      start[c] = held[c]->centre_m;
      target[c] = stage.poses[c].position_m;
    }
    ShellSolveReport report;
    if (fell) {
      report = solve(options.fall_damping_1_s2);
      if (!report.converged) {
        result.failure = fmt::format("stage {}: the sheet did not settle after it was let go ({})", k + 1, report.message);
        return result;
      }
    }
    double travel = 0;
    for (std::size_t c = 0; c < jaws.size(); ++c) {
      if (held[c]) travel = std::max(travel, (target[c] - start[c]).norm());
    }
    const int increments = std::max(1, static_cast<int>(std::ceil(travel / options.increment_m)));
    if (travel == 0 && !fell) report = solve(0.0);
    VecX previous;  // the last increment's equilibrium, for the secant predictor
    for (int i = 1; i <= increments && travel > 0; ++i) {
      const double t = static_cast<double>(i) / increments;
      for (std::size_t c = 0; c < jaws.size(); ++c) {
        if (held[c]) held[c]->centre_m = start[c] + t * (target[c] - start[c]);
      }
      // Predictor: equal increments along one straight move change the shape about equally.
      const VecX converged = x;
      if (previous.size() == x.size()) x += x - previous;
      report = solve(0.0);
      if (!report.converged) {
        x = converged;
        report = solve(0.0);
      }
      previous = converged;
      if (!report.converged) report = solve(options.fall_damping_1_s2);  // a snap: let it move there damped
      if (!report.converged) {
        result.failure = fmt::format("stage {}: increment {} of {}: {}", k + 1, i, increments, report.message);
        return result;
      }
    }
    if (!report.converged) {
      result.failure = fmt::format("stage {}: {}", k + 1, report.message);
      return result;
    }
    if (model.material().creep_fraction > 0) {
      model.set_age_s(stage.age_s);
      report = solve(0.0);
      if (!report.converged) report = solve(options.fall_damping_1_s2);
      if (!report.converged) {
        result.failure = fmt::format("stage {}: creep to age {} s: {}", k + 1, stage.age_s, report.message);
        return result;
      }
    }
    result.stages.push_back(x);
    result.holds.push_back(holds());
    result.reports.push_back(report);
  }
  return result;
}

VecX carry_to_patch(const ShellModel& from, const VecX& x, const ShellHolds& holds, const ShellModel& to,
                    const ShellPathOptions& options, ShellSolveReport* report) {
  VecX y = refine_controls(from.patch(), x, to.patch());
  ShellSolveReport r = solve_shell(to, holds, y, options.solve);
  if (!r.converged) {
    ShellSolveOptions damped = options.solve;
    damped.initial_damping_1_s2 = options.fall_damping_1_s2;
    damped.max_iterations = std::max(damped.max_iterations, 5000);
    r = solve_shell(to, holds, y, damped);
  }
  if (report) *report = r;
  if (!r.converged) throw std::runtime_error("spline shell: the shape carried to the finer patch did not settle: " + r.message);
  return y;
}

}  // namespace sim_hw::spline_shell
