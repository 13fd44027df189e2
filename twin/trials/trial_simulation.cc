#include "twin/trials/trial_simulation.h"

#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/trials/stage_age.h"

namespace twin {

bool TrialSimulation::usable() const {
  return failure.empty() && !stages.empty() && stages.back().report.usable();
}

SheetPlacement fit_level_placement(const std::vector<ClampSpec>& clamps,
                                   const std::vector<ClampPose>& poses) {
  std::vector<Vec2> from, to;
  double height = 0.0;
  for (std::size_t i = 0; i < clamps.size() && i < poses.size(); ++i) {
    if (!poses[i].engaged) continue;
    from.push_back(clamps[i].material_point_m);
    to.push_back(poses[i].position_m.head<2>());
    height += poses[i].position_m.z();
  }
  if (from.empty()) throw std::invalid_argument("no clamp holds the sheet in the first stage");
  height /= static_cast<double>(from.size());
  Vec2 from_mean = Vec2::Zero(), to_mean = Vec2::Zero();
  for (std::size_t i = 0; i < from.size(); ++i) {
    from_mean += from[i];
    to_mean += to[i];
  }
  from_mean /= static_cast<double>(from.size());
  to_mean /= static_cast<double>(from.size());
  // 2D Procrustes: the angle maximising sum of (R a_i) . b_i over centred points.
  double dot = 0.0, cross = 0.0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Vec2 a = from[i] - from_mean, b = to[i] - to_mean;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  const double angle = from.size() > 1 ? std::atan2(cross, dot) : 0.0;
  SheetPlacement placement;
  placement.rotation = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
  const Vec2 shift = to_mean - placement.rotation.topLeftCorner<2, 2>() * from_mean;
  placement.origin_m = Vec3(shift.x(), shift.y(), height);
  return placement;
}

TrialSimulation simulate_stages(ShellModel& model, const ClampSet& clamps,
                                const std::vector<TrialStage>& stages,
                                const ContinuationOptions& options,
                                const StageReached& on_stage) {
  TrialSimulation result;
  if (stages.empty()) {
    result.failure = "the trial has no stages";
    return result;
  }
  std::vector<ClampSpec> specs;
  for (int i = 0; i < clamps.size(); ++i) specs.push_back(clamps[i].spec());
  const SheetPlacement placement = fit_level_placement(specs, stages.front().poses);
  VecX x = place_flat(model.mesh(), placement);
  // Nothing grips the flat sheet yet: each clamp closes on it where its material point lies.
  std::vector<ClampPose> poses(specs.size());
  for (ClampPose& p : poses) p.engaged = false;
  QuasiStaticSolver solver(model, clamps);
  const std::vector<double> ages_s = stage_load_ages_s(stages);
  const bool relaxes = model.material().effects.relaxation_fraction != 0.0;
  std::unique_ptr<StaticSolver> relaxation;  // only needed (and built) when the material relaxes
  if (relaxes) relaxation = std::make_unique<StaticSolver>(model);
  for (std::size_t k = 0; k < stages.size(); ++k) {
    const TrialStage& stage = stages[k];
    StageSimulation s;
    s.id = stage.id;
    // The clamps' jaws stay as they closed on the level sheet: they travel without turning.
    std::vector<ClampPose> target = stage.poses;
    for (ClampPose& p : target) p.rotation = placement.rotation;
    model.set_load_age_s(0.0);  // the move: a fresh load (see the header)
    s.report = solver.move(poses, target, x, options);
    if (s.report.usable() && relaxes) {
      model.set_load_age_s(ages_s[k]);
      const SolveReport relaxed = relaxation->solve(clamps, target, x, options.newton);
      s.report.last = relaxed;
      s.report.newton_iterations += relaxed.iterations;
      s.report.factorizations += relaxed.factorizations;
    }
    if (!s.report.usable()) {
      result.failure = fmt::format("stage {}: {}", stage.id, s.report.brief());
      result.stages.push_back(std::move(s));
      return result;
    }
    poses = target;
    s.x = x;
    if (on_stage) on_stage(k, s.x);
    result.stages.push_back(std::move(s));
  }
  return result;
}

}  // namespace twin
