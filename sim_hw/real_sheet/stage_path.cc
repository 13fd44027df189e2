#include "sim_hw/real_sheet/stage_path.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <Eigen/Geometry>
#include <fmt/format.h>

namespace sim_hw::real_sheet {

std::vector<PathStage> path_stages(const std::vector<twin::TrialStage>& stages) {
  std::vector<PathStage> out(stages.size());
  for (std::size_t k = 0; k < stages.size(); ++k) {
    out[k].poses = stages[k].poses;
    if (stages[k].time_s && stages[k].clamps_moved_at_s) out[k].age_s = *stages[k].time_s - *stages[k].clamps_moved_at_s;
  }
  return out;
}
namespace {

// The jaws' pads for the clamps, with the material's wide and slipping jaws.
std::vector<JawPad> make_pads(const SheetModel& model, const std::vector<twin::ClampSpec>& clamps,
                              const PathOptions& options) {
  std::vector<JawPad> pads;
  for (const twin::ClampSpec& c : clamps) {
    JawPadOptions o = options.pad;
    o.grip_radius_m = c.grip_radius_m;
    o.extension_m = model.material().pad_extension_m;
    o.extension_strength = model.material().pad_strength;
    o.slip_compliance_m_N = model.material().slip_compliance_m_N;
    pads.push_back(make_jaw_pad(model.grid(), c.id, c.material_point_m, options.jaws, o));
  }
  return pads;
}

// The sheet's own frame at a material point (u, v tangents and normal, orthonormalised), for a
// jaw that closes on the hanging sheet.
Eigen::Matrix3d frame_at(const SheetModel& model, const VecX& x, const Vec2& uv) {
  const Grid& grid = model.grid();
  const Vec3 p = grid.position(x, grid.locate(uv));
  const Vec3 pu = grid.position(x, grid.locate(uv + Vec2(grid.cell_size_at(uv).x() * 0.5, 0))) - p;
  const Vec3 n = model.normal_at(x, uv);
  Vec3 u = (pu - pu.dot(n) * n).normalized();
  Eigen::Matrix3d R;
  R.col(0) = u;
  R.col(1) = n.cross(u);
  R.col(2) = n;
  return R;
}

}  // namespace

VecX carry_to_grid(const SheetModel& from, const VecX& x, const std::vector<JawHold>& holds, const SheetModel& to,
                   const PathOptions& options, EquilibriumReport* report) {
  const Grid& a = from.grid();
  const Grid& b = to.grid();
  VecX y(3 * b.node_count());
  for (int n = 0; n < b.node_count(); ++n) y.segment<3>(3 * n) = a.smooth_position(x, b.rest_uv(n));
  std::vector<JawHold> carried = holds;
  for (JawHold& j : carried) {
    JawPadOptions o = options.pad;
    o.grip_radius_m = j.pad.grip_radius_m;
    o.extension_m = to.material().pad_extension_m;
    o.extension_strength = to.material().pad_strength;
    o.slip_compliance_m_N = to.material().slip_compliance_m_N;
    j.pad = make_jaw_pad(b, j.pad.id, j.pad.material_point_m, j.pad.kind, o);
  }
  EquilibriumReport r = solve_equilibrium(to, y, carried, options.equilibrium);
  if (!r.converged) {
    EquilibriumOptions damped = options.equilibrium;
    damped.initial_damping_1_s2 = 1e4;
    damped.max_iterations = std::max(damped.max_iterations, 5000);
    r = solve_equilibrium(to, y, carried, damped);
  }
  if (report) *report = r;
  if (!r.converged) throw std::runtime_error("real sheet: the shape carried to the finer grid did not settle: " + r.message);
  return y;
}

LevelPlacement level_placement(const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::ClampPose>& poses) {
  std::vector<Vec2> from, to;
  double height = 0;
  for (std::size_t i = 0; i < clamps.size(); ++i) {
    if (!poses[i].engaged) continue;
    from.push_back(clamps[i].material_point_m);
    to.push_back(poses[i].position_m.head<2>());
    height += poses[i].position_m.z();
  }
  if (from.empty()) throw std::invalid_argument("real sheet: no clamp holds the first stage");
  Vec2 cf = Vec2::Zero(), ct = Vec2::Zero();
  for (std::size_t k = 0; k < from.size(); ++k) cf += from[k], ct += to[k];
  cf /= from.size();
  ct /= from.size();
  // 2-D Procrustes: the angle maximising sum (R a) . b.
  double s = 0, c = 0;
  for (std::size_t k = 0; k < from.size(); ++k) {
    const Vec2 a = from[k] - cf, b = to[k] - ct;
    c += a.dot(b);
    s += a.x() * b.y() - a.y() * b.x();
  }
  const double angle = from.size() > 1 ? std::atan2(s, c) : 0.0;
  LevelPlacement p;
  p.rotation = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 shifted = Vec3(ct.x(), ct.y(), height / from.size()) - p.rotation * Vec3(cf.x(), cf.y(), 0.0);
  p.origin_m = shifted;
  return p;
}

PathResult simulate_path(SheetModel& model, const std::vector<twin::ClampSpec>& clamps,
                         const std::vector<PathStage>& stages, const PathOptions& options) {
  PathResult result;
  if (stages.empty()) {
    result.failure = "the trial has no stages";
    return result;
  }
  const LevelPlacement placement = level_placement(clamps, stages.front().poses);
  const Grid& grid = model.grid();
  VecX x(3 * grid.node_count());
  for (int n = 0; n < grid.node_count(); ++n) x.segment<3>(3 * n) = placement.to_world(grid.rest_uv(n));
  const std::vector<JawPad> pads = make_pads(model, clamps, options);
  // Which clamp holds, with its pose; none yet: each closes on the flat sheet as it engages.
  std::vector<std::optional<JawHold>> held(clamps.size());
  const auto holds = [&] {
    std::vector<JawHold> h;
    for (const auto& j : held) {
      if (j) h.push_back(*j);
    }
    return h;
  };
  const auto write_back = [&](const std::vector<JawHold>& h) {
    std::size_t k = 0;
    for (auto& j : held) {
      if (j) *j = h[k++];
    }
  };
  const auto solve = [&](double damping) {
    std::vector<JawHold> h = holds();
    EquilibriumOptions o = options.equilibrium;
    o.initial_damping_1_s2 = damping;
    // A fall is a long overdamped motion (a released corner swings half a metre).
    if (damping > 0) o.max_iterations = std::max(o.max_iterations, 5000);
    const EquilibriumReport r = solve_equilibrium(model, x, h, o);
    result.iterations += r.iterations;
    result.factorizations += r.factorizations;
    ++result.increments;
    if (r.converged) write_back(h);
    return r;
  };
  // A fall (first grip, a jaw opening): start damped, as an overdamped sheet falls.
  const double fall_damping = 1e4;

  for (std::size_t k = 0; k < stages.size(); ++k) {
    const PathStage& stage = stages[k];
    if (stage.poses.size() != clamps.size()) throw std::invalid_argument("real sheet: a stage must pose every clamp");
    model.set_age_s(0.0);
    bool fell = false;
    std::vector<Vec3> start(clamps.size()), target(clamps.size());
    for (std::size_t c = 0; c < clamps.size(); ++c) {
      if (!stage.poses[c].engaged) {
        fell |= held[c].has_value();
        held[c].reset();
        continue;
      }
      if (!held[c]) {
        JawHold j;
        j.pad = pads[c];
        j.centre_m = grid.position(x, grid.locate(clamps[c].material_point_m));
        j.rotation = k == 0 ? placement.rotation : frame_at(model, x, clamps[c].material_point_m);
        held[c] = j;
        fell |= k == 0;
      }
      start[c] = held[c]->centre_m;
      target[c] = stage.poses[c].position_m;
    }
    EquilibriumReport report;
    if (fell) {
      report = solve(fall_damping);
      if (!report.converged) {
        result.failure = fmt::format("stage {}: the sheet did not settle after it was let go ({})", k + 1, report.message);
        return result;
      }
    }
    double travel = 0;
    for (std::size_t c = 0; c < clamps.size(); ++c) {
      if (held[c]) travel = std::max(travel, (target[c] - start[c]).norm());
    }
    const int increments = std::max(1, static_cast<int>(std::ceil(travel / options.increment_m)));
    if (travel == 0 && !fell) report = solve(0.0);
    VecX previous;  // the last increment's equilibrium, for the secant predictor
    for (int i = 1; i <= increments && travel > 0; ++i) {
      const double t = static_cast<double>(i) / increments;
      for (std::size_t c = 0; c < clamps.size(); ++c) {
        if (held[c]) held[c]->centre_m = start[c] + t * (target[c] - start[c]);
      }
      // Predictor: equal increments along one straight move change the shape about equally, so
      // the next equilibrium starts from the last one plus the last change (a secant step); the
      // corrector then has a shape near the answer, not one with the jaws 2 cm off their patch.
      const VecX converged = x;
      if (previous.size() == x.size()) {
        x += x - previous;
        if (!std::isfinite(model.energy(x, holds(), nullptr, nullptr, Hessian::kExact))) x = converged;
      }
      report = solve(0.0);
      if (!report.converged) {
        x = converged;
        report = solve(0.0);
      }
      previous = converged;
      if (!report.converged) report = solve(fall_damping);  // a snap: let it move there damped
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
      if (!report.converged) report = solve(fall_damping);
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

}  // namespace sim_hw::real_sheet
