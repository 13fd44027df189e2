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

namespace {

// The handling's state between stages: the sheet's controls and which jaws hold it where.
class PathWalker {
 public:
  PathWalker(ShellModel& model, const std::vector<SquareJaw>& jaws, const ShellPathOptions& options,
             ShellPathResult& counts)
      : model_(model), jaws_(jaws), options_(options), counts_(counts), held_(jaws.size()) {}

  // The flat sheet, level, placed for the first stage's poses (real_sheet::level_placement).
  void place_level(const std::vector<twin::ClampPose>& first_poses) {
    std::vector<twin::ClampSpec> specs;
    for (const SquareJaw& j : jaws_) specs.push_back(twin::ClampSpec{j.id, j.material_point_m, j.half_side_m});
    const real_sheet::LevelPlacement placement = real_sheet::level_placement(specs, first_poses);
    const SplinePatch& patch = model_.patch();
    const std::vector<double> gu = patch.u().greville(), gv = patch.v().greville();
    x_.resize(model_.dof_count());
    for (int j = 0; j < patch.nv(); ++j) {
      for (int i = 0; i < patch.nu(); ++i) x_.segment<3>(3 * patch.control(i, j)) = placement.to_world(Vec2(gu[i], gv[j]));
    }
    level_rotation_ = placement.rotation;
  }

  // An equilibrium reached before, held as `holds` says (jaws by id).
  void start_from(const VecX& x, const ShellHolds& holds) {
    x_ = x;
    for (std::size_t c = 0; c < jaws_.size(); ++c) {
      held_[c].reset();
      for (const JawHold& h : holds.jaws) {
        if (h.jaw.id == jaws_[c].id) held_[c] = h;
      }
    }
  }

  const VecX& x() const { return x_; }
  ShellHolds holds() const {
    ShellHolds h;
    for (const auto& j : held_) {
      if (j) h.jaws.push_back(*j);
    }
    return h;
  }

  // Takes the sheet to the stage's poses; empty on success, else what failed.
  std::string advance(const real_sheet::PathStage& stage, ShellSolveReport& report) {
    if (stage.poses.size() != jaws_.size()) throw std::invalid_argument("spline shell: a stage must pose every clamp");
    model_.set_age_s(0.0);
    bool fell = false;
    std::vector<Vec3> start(jaws_.size()), target(jaws_.size());
    const SplinePatch& patch = model_.patch();
    for (std::size_t c = 0; c < jaws_.size(); ++c) {
      if (!stage.poses[c].engaged) {
        fell |= held_[c].has_value();
        held_[c].reset();
        continue;
      }
      if (!held_[c]) {
        JawHold j;
        j.jaw = jaws_[c];
        j.centre_m = patch.position(x_, jaws_[c].material_point_m);
        j.rotation = level_rotation_ ? *level_rotation_ : frame_at(patch, x_, jaws_[c].material_point_m);
        held_[c] = j;
        fell = true;  // the first grip lets the level sheet go; a later one snaps the pad flat
      }
      start[c] = held_[c]->centre_m;
      target[c] = stage.poses[c].position_m;
    }
    level_rotation_.reset();  // only the grips on the level sheet take its frame
    if (fell) {
      report = solve(options_.fall_damping_1_s2);
      if (!report.converged) return fmt::format("the sheet did not settle after it was let go ({})", report.message);
    }
    double travel = 0;
    for (std::size_t c = 0; c < jaws_.size(); ++c) {
      if (held_[c]) travel = std::max(travel, (target[c] - start[c]).norm());
    }
    const int increments = std::max(1, static_cast<int>(std::ceil(travel / options_.increment_m)));
    if (travel == 0 && !fell) report = solve(0.0);
    VecX previous;  // the last increment's equilibrium, for the secant predictor
    for (int i = 1; i <= increments && travel > 0; ++i) {
      const double t = static_cast<double>(i) / increments;
      for (std::size_t c = 0; c < jaws_.size(); ++c) {
        if (held_[c]) held_[c]->centre_m = start[c] + t * (target[c] - start[c]);
      }
      // Predictor: equal increments along one straight move change the shape about equally.
      const VecX converged = x_;
      if (previous.size() == x_.size()) x_ += x_ - previous;
      report = solve(0.0);
      if (!report.converged) {
        x_ = converged;
        report = solve(0.0);
      }
      previous = converged;
      if (!report.converged) report = solve(options_.fall_damping_1_s2);  // a snap: let it move there damped
      if (!report.converged) return fmt::format("increment {} of {}: {}", i, increments, report.message);
    }
    if (!report.converged) return report.message;
    if (model_.material().creep_fraction > 0) {
      model_.set_age_s(stage.age_s);
      report = solve(0.0);
      if (!report.converged) report = solve(options_.fall_damping_1_s2);
      if (!report.converged) return fmt::format("creep to age {} s: {}", stage.age_s, report.message);
    }
    return {};
  }

 private:
  ShellSolveReport solve(double damping) {
    ShellSolveOptions o = options_.solve;
    o.initial_damping_1_s2 = damping;
    // A fall is a long overdamped motion (a released corner swings half a metre).
    if (damping > 0) o.max_iterations = std::max(o.max_iterations, 5000);
    const ShellSolveReport r = solve_shell(model_, holds(), x_, o);
    counts_.iterations += r.iterations;
    counts_.factorizations += r.factorizations;
    ++counts_.increments;
    return r;
  }

  ShellModel& model_;
  const std::vector<SquareJaw>& jaws_;
  const ShellPathOptions& options_;
  ShellPathResult& counts_;
  std::vector<std::optional<JawHold>> held_;
  VecX x_;
  std::optional<Eigen::Matrix3d> level_rotation_;
};

}  // namespace

ShellPathResult follow_path(ShellModel& model, const std::vector<SquareJaw>& jaws,
                            const std::vector<real_sheet::PathStage>& stages, const ShellPathOptions& options) {
  ShellPathResult result;
  if (stages.empty()) {
    result.failure = "the trial has no stages";
    return result;
  }
  PathWalker walker(model, jaws, options, result);
  walker.place_level(stages.front().poses);
  for (std::size_t k = 0; k < stages.size(); ++k) {
    ShellSolveReport report;
    const std::string failure = walker.advance(stages[k], report);
    if (!failure.empty()) {
      result.failure = fmt::format("stage {}: {}", k + 1, failure);
      return result;
    }
    result.stages.push_back(walker.x());
    result.holds.push_back(walker.holds());
    result.reports.push_back(report);
  }
  return result;
}

bool lets_go(const ShellHolds& before, const real_sheet::PathStage& stage, const std::vector<SquareJaw>& jaws) {
  for (std::size_t c = 0; c < jaws.size() && c < stage.poses.size(); ++c) {
    bool held = false;
    for (const JawHold& h : before.jaws) held |= h.jaw.id == jaws[c].id;
    if (held != stage.poses[c].engaged) return true;
  }
  return false;
}

VecX replay_stage(ShellModel& model, const std::vector<SquareJaw>& jaws, const VecX& x, const ShellHolds& holds,
                  const real_sheet::PathStage& stage, ShellHolds* holds_after, const ShellPathOptions& options,
                  ShellSolveReport* report) {
  ShellPathResult counts;
  PathWalker walker(model, jaws, options, counts);
  walker.start_from(x, holds);
  ShellSolveReport r;
  const std::string failure = walker.advance(stage, r);
  r.iterations = counts.iterations;
  r.factorizations = counts.factorizations;
  if (report) *report = r;
  if (!failure.empty()) throw std::runtime_error("spline shell: " + failure);
  if (holds_after) *holds_after = walker.holds();
  return walker.x();
}

VecX carry_to_patch(const ShellModel& from, const VecX& x, const ShellHolds& holds, const ShellModel& to,
                    const ShellPathOptions& options, ShellSolveReport* report) {
  VecX y = refine_controls(from.patch(), x, to.patch());
  ShellSolveOptions relaxed = options.solve;
  relaxed.relax_to_force = options.carry_relax_to_force;
  ShellSolveReport r = solve_shell(to, holds, y, relaxed);
  if (!r.converged) {
    ShellSolveOptions damped = options.solve;
    damped.initial_damping_1_s2 = options.fall_damping_1_s2;
    damped.max_iterations = std::max(damped.max_iterations, 5000);
    const ShellSolveReport first = r;
    r = solve_shell(to, holds, y, damped);
    r.iterations += first.iterations;
    r.relaxation_iterations += first.relaxation_iterations;
  }
  if (report) *report = r;
  if (!r.converged) throw std::runtime_error("spline shell: the shape carried to the finer patch did not settle: " + r.message);
  return y;
}

double stage_age_s(const ShellModel& model, const real_sheet::PathStage& stage) {
  return model.material().creep_fraction > 0 ? stage.age_s : 0.0;
}

CarriedPath carry_path(ShellModel& from, const std::vector<VecX>& x, const std::vector<ShellHolds>& holds, ShellModel& to,
                       const std::vector<SquareJaw>& jaws, const std::vector<real_sheet::PathStage>& stages,
                       const ShellPathOptions& options) {
  if (x.size() != stages.size() || holds.size() != stages.size()) {
    throw std::invalid_argument("spline shell: carry_path needs one state and one hold per stage");
  }
  CarriedPath out;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double age_s = stage_age_s(from, stages[k]);
    if (k > 0 && x[k] == x[k - 1] && age_s == stage_age_s(from, stages[k - 1])) {  // a repeated scan of one pose
      out.stages.push_back(out.stages.back());
      out.holds.push_back(out.holds.back());
      continue;
    }
    ShellSolveReport report;
    try {
      if (options.replay_falls && k > 0 && lets_go(out.holds.back(), stages[k], jaws)) {
        ShellHolds after;
        out.stages.push_back(replay_stage(to, jaws, out.stages.back(), out.holds.back(), stages[k], &after, options, &report));
        out.holds.push_back(after);
        out.replayed.push_back(static_cast<int>(k));
      } else {
        ShellHolds h = holds[k];
        if (k > 0) {
          for (JawHold& j : h.jaws) {
            for (const JawHold& before : out.holds.back().jaws) {
              if (before.jaw.id == j.jaw.id) j.rotation = before.rotation;
            }
          }
        }
        from.set_age_s(age_s);
        to.set_age_s(age_s);
        out.stages.push_back(carry_to_patch(from, x[k], h, to, options, &report));
        out.holds.push_back(h);
      }
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("stage {}: {}", k + 1, e.what()));
    }
    out.iterations += report.iterations;
    out.relaxation_iterations += report.relaxation_iterations;
  }
  return out;
}

}  // namespace sim_hw::spline_shell
