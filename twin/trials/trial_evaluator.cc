#include "twin/trials/trial_evaluator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "twin/trials/continuation_start.h"
#include "twin/base/job_lanes.h"
#include "twin/mesh/observed_shape.h"
#include "twin/solvers/scan_tether.h"
#include "twin/trials/stage_age.h"
#include "twin/trials/trial_simulation.h"

namespace twin {
namespace {

VecX search_coordinates(const Material& material, const std::vector<MaterialParameter>& parameters) {
  VecX v(static_cast<Eigen::Index>(parameters.size()));
  for (std::size_t j = 0; j < parameters.size(); ++j) v(j) = to_search_coordinate(parameters[j], get_parameter(material, parameters[j]));
  return v;
}

// One scored observation: which vertices predict it, with which weights.
struct Pairing {
  std::array<int, 3> vertices{};
  Vec3 weights = Vec3::Zero();
  Vec3 observed = Vec3::Zero();
  Vec3 predicted(const VecX& x) const {
    return weights(0) * x.segment<3>(3 * vertices[0]) + weights(1) * x.segment<3>(3 * vertices[1]) +
           weights(2) * x.segment<3>(3 * vertices[2]);
  }
};

std::vector<Pairing> pairings(const StageObservation& observed, const MaterialPointMap& markers, const VecX& x) {
  std::vector<Pairing> result;
  if (observed.has_markers()) {
    for (std::size_t i = 0; i < observed.markers_m.size(); ++i) {
      if (!observed.markers_m[i].allFinite()) continue;
      const MaterialPointLocation& at = markers.location(static_cast<int>(i));
      result.push_back({at.vertices, at.weights, observed.markers_m[i]});
    }
  } else {
    const std::vector<int> nearest = nearest_vertices(observed.cloud_m, x);
    for (std::size_t i = 0; i < nearest.size(); ++i) {
      if (nearest[i] < 0) continue;
      result.push_back({{nearest[i], nearest[i], nearest[i]}, Vec3(1.0, 0.0, 0.0), observed.cloud_m[i]});
    }
  }
  return result;
}

}  // namespace

double TrialFit::nearest_score_m(double max_weight) const {
  double sum = 0.0;
  for (const StageFit& s : stages) sum += s.nearest.score(max_weight);
  return sum;
}

TrialEvaluator::TrialEvaluator(Trial trial, const TwinMeshSpec& twin_mesh, const Material& material)
    : trial_(std::move(trial)),
      model_(std::make_unique<ShellModel>(trial_sheet_mesh(trial_, twin_mesh), material)),
      clamps_(model_->mesh(), trial_.clamps),
      markers_(std::make_unique<MaterialPointMap>(model_->mesh(), trial_.marker_uv_m)),
      placement_(fit_level_placement(trial_.clamps, trial_.stages.at(0).poses)),
      statics_(std::make_unique<StaticSolver>(*model_)),
      sensitivities_(trial_.stages.size()),
      ages_s_(stage_load_ages_s(trial_.stages)) {
  model_->set_marker_points(*markers_);  // their mass, when the material gives them one
  model_->set_clamp_grips(clamps_);       // their width, when the material widens them
  model_->set_clamp_slips(clamps_);       // their give, when the material lets them slip
  build_path_model(twin_mesh);
}

void TrialEvaluator::build_path_model(const TwinMeshSpec& spec) {
  if (spec.path_triangles <= 0) return;
  SheetMesh coarse = trial_sheet_mesh(trial_, spec.path_triangles);
  // Worth it only when it is well under the twin (a sheet given as a mesh file stays as given).
  if (3 * coarse.triangle_count() >= 2 * model_->mesh().triangle_count()) return;
  try {
    auto model = std::make_unique<ShellModel>(std::move(coarse), model_->material());
    auto clamps = std::make_unique<ClampSet>(model->mesh(), trial_.clamps);
    auto markers = std::make_unique<MaterialPointMap>(model->mesh(), trial_.marker_uv_m);
    auto to_twin = std::make_unique<MaterialPointMap>(model->mesh(), model_->mesh().rest_uv);
    model->set_marker_points(*markers);
    model->set_clamp_grips(*clamps);
    model->set_clamp_slips(*clamps);
    path_model_ = std::move(model);
    path_clamps_ = std::move(clamps);
    path_markers_ = std::move(markers);
    path_to_twin_ = std::move(to_twin);
  } catch (const std::invalid_argument&) {
    // A twin vertex or clamp the coarse mesh does not cover: follow the path on the twin.
  }
}

std::unique_ptr<ShellModel> TrialEvaluator::build_model(SheetMesh mesh, const Material& material) const {
  auto model = std::make_unique<ShellModel>(std::move(mesh), material);
  model->set_marker_points(*markers_);
  model->set_clamp_grips(clamps_);
  model->set_clamp_slips(clamps_);
  return model;
}

ShellModel& TrialEvaluator::lane_model(int lane) {
  if (lane == 0) return *model_;
  return *second_lane_model_;
}

TrialEvaluator::~TrialEvaluator() = default;

std::vector<ClampPose> TrialEvaluator::stage_poses(int stage) const {
  // As in simulate_stages: the jaws keep the orientation in which they closed on the level sheet.
  std::vector<ClampPose> poses = trial_.stages[stage].poses;
  for (ClampPose& p : poses) p.rotation = placement_.rotation;
  return poses;
}

ContinuationStarts TrialEvaluator::continuation_cached(const VecX& coordinates) const {
  std::vector<EvaluatedMaterial> evaluated;
  evaluated.reserve(cache_.size());
  for (const CachedEquilibria& c : cache_) evaluated.push_back({c.coordinates, c.sum_squares_m2});
  const double one_step = std::log(kMaterialStepRatio);
  return continuation_starts(evaluated, coordinates, one_step, one_step * kMaxMaterialSteps);
}

bool TrialEvaluator::simulate_warm(const CachedEquilibria& start, const Material& target,
                                   const std::vector<MaterialParameter>& parameters, TrialFit& fit) {
  const VecX from = start.coordinates, to = search_coordinates(target, parameters);
  const int steps =
      std::max(1, static_cast<int>(std::ceil((to - from).cwiseAbs().maxCoeff() / std::log(kMaterialStepRatio) - 1e-9)));
  std::vector<VecX> x = start.stage_x;
  for (int k = 1; k <= steps; ++k) {
    // Geometric interpolation of the varied parameters; the rest is the target's.
    Material m = target;
    const VecX at = from + (to - from) * (static_cast<double>(k) / steps);
    for (std::size_t j = 0; j < parameters.size(); ++j) set_parameter(m, parameters[j], from_search_coordinate(parameters[j], at(j)));
    model_->set_material(m);
    for (std::size_t s = 0; s < trial_.stages.size(); ++s) {
      model_->set_load_age_s(ages_s_[s]);
      const SolveReport r = statics_->solve(clamps_, stage_poses(static_cast<int>(s)), x[s]);
      fit.newton_iterations += r.iterations;
      if (!r.usable()) {
        model_->set_material(target);
        return false;
      }
    }
  }
  fit.stages.clear();
  for (std::size_t s = 0; s < trial_.stages.size(); ++s) {
    StageFit stage;
    stage.id = trial_.stages[s].id;
    stage.x = std::move(x[s]);
    fit.stages.push_back(std::move(stage));
  }
  return true;
}

bool TrialEvaluator::simulate_cold(TrialFit& fit, bool coarse_path_allowed) {
  fit.stages.clear();
  // (With the path on a coarse mesh, trial_evaluator.h, its equilibria only start the second
  // tether below and are not candidates themselves.)
  // Besides the path, every marker stage is tethered to its scan and let go (scan_tether.h),
  // from two starts: the shape interpolated from the markers, and the path's own equilibrium
  // pinned to the scan and let go slowly. Both end at equilibria of the same material in the
  // basin the real sheet was seen in, or near it; keep whichever of the three the markers are
  // nearest. The second matters where the path has the right shape but for one wrinkle or
  // fold: the interpolated shape is coarse between markers (7 cm apart in the lab), and from it
  // the sheet can settle into a neighbouring basin. Measured on eight lab composite trials
  // (true material, twin on the lab's own 1539-triangle mesh, errors against the noise-free
  // markers, mean over stages): 0.33-3.80 mm with the interpolated start alone, 0.10-0.43 mm
  // with both. Neither start is best on every stage (on twins coarser than the lab's sheet,
  // either beat the other by 1.5-10 mm on some stage), hence both.
  //
  // The path runs on lane 0; the tethered solves are jobs for either lane: those from the
  // interpolated shapes at once, those from the path's equilibria as the path reaches each
  // stage. Each lane solves on its own model (the model's load age and clamp state change per
  // solve). Measured on the benchmark trial (1539 triangles, one thread per solve): path 6.0 s,
  // interpolated starts 3.0 s, path starts 4.9 s.
  const std::size_t stage_count = trial_.stages.size();
  enum Start { kInterpolated = 0, kFromPath = 1 };
  struct Tethered {
    VecX x;
    SolveReport report;
    bool ran = false;
  };
  std::vector<std::array<Tethered, 2>> tethered(stage_count);
  const auto tethers_scan = [&](std::size_t s) {
    const StageObservation& observed = trial_.stages[s].observed;
    return observed.has_markers() && observed.seen_marker_count() >= 3;
  };
  const auto tether = [&](int lane, std::size_t s, Start start, VecX x) {
    ShellModel& model = lane_model(lane);
    model.set_load_age_s(ages_s_[s]);  // the equilibrium the scan saw: at the scan's age
    Tethered& t = tethered[s][start];
    t.report = equilibrium_from_scan(model, clamps_, stage_poses(static_cast<int>(s)), *markers_,
                                     trial_.stages[s].observed.markers_m, x,
                                     start == kInterpolated ? TetherRelease{} : kPinnedTetherRelease);
    t.x = std::move(x);
    t.ran = true;
  };
  // The path on the coarse mesh when every stage has a tether to choose its equilibrium
  // (trial_evaluator.h); its equilibria are then starts, not candidates.
  bool coarse_path = coarse_path_allowed && path_model_ != nullptr;
  for (std::size_t s = 0; s < stage_count && coarse_path; ++s) coarse_path = tethers_scan(s);
  const auto on_twin = [&](const VecX& coarse_x) {
    const std::vector<Vec3> p = path_to_twin_->positions(coarse_x);
    VecX x(3 * static_cast<Eigen::Index>(p.size()));
    for (std::size_t i = 0; i < p.size(); ++i) x.segment<3>(3 * static_cast<Eigen::Index>(i)) = p[i];
    return x;
  };
  if (coarse_path) path_model_->set_material(model_->material());
  constexpr int kLanes = 2;
  if (available_lanes(kLanes) > 1) {
    if (!second_lane_model_) second_lane_model_ = build_model(model_->mesh(), model_->material());
    second_lane_model_->set_material(model_->material());
  }
  JobQueue jobs;
  for (std::size_t s = 0; s < stage_count; ++s) {
    if (!tethers_scan(s)) continue;
    VecX start = shape_from_markers(model_->mesh(), trial_.marker_uv_m, trial_.stages[s].observed.markers_m);
    jobs.push([&tether, s, start = std::move(start)](int lane) { tether(lane, s, kInterpolated, start); });
  }
  TrialSimulation simulated;
  run_lanes(kLanes, jobs, [&] {
    const StageReached reached = [&](std::size_t s, const VecX& x) {
      if (!tethers_scan(s)) return;
      jobs.push([&tether, s, x = coarse_path ? on_twin(x) : x](int lane) { tether(lane, s, kFromPath, x); });
    };
    simulated = coarse_path ? simulate_stages(*path_model_, *path_clamps_, trial_.stages, {}, reached)
                            : simulate_stages(*model_, clamps_, trial_.stages, {}, reached);
  });

  for (const StageSimulation& s : simulated.stages) fit.newton_iterations += s.report.newton_iterations;
  // Every stage's candidate equilibria: the path's own when it is the twin's, then the tethered
  // ones that converged.
  struct Candidate {
    const VecX* x;
    std::size_t stage;  // whose load age it was solved at
    bool from_scan;
  };
  std::vector<std::vector<Candidate>> candidates(stage_count);
  for (std::size_t s = 0; s < stage_count; ++s) {
    if (!coarse_path && s < simulated.stages.size() && simulated.stages[s].x.size() > 0) {
      candidates[s].push_back({&simulated.stages[s].x, s, false});
    }
    for (Tethered& t : tethered[s]) {  // interpolated first, then from the path, as the lanes ran them
      if (!t.ran) continue;
      fit.newton_iterations += t.report.iterations;
      if (t.report.usable()) candidates[s].push_back({&t.x, s, true});
    }
  }
  const auto misfit = [&](std::size_t s, const VecX& x) {
    return correspondence_error(trial_.stages[s].observed.markers_m, markers_->positions(x)).mean_m;
  };
  // Scans of one pose, one after another with nothing moved between them, see one sheet: they
  // are predicted on one equilibrium, the candidate that fits all their scans together, so the
  // branch does not follow each scan's noise (scored one by one, three scans of one pose were
  // predicted on three different folds). Each scan keeps its own load age: under relaxation
  // the chosen equilibrium is carried to that age by a static solve from it (same branch).
  for (std::size_t first = 0; first < stage_count;) {
    std::size_t end = first + 1;
    while (end < stage_count && same_clamp_poses(trial_.stages[end - 1], trial_.stages[end])) ++end;
    std::vector<std::size_t> scored;
    for (std::size_t s = first; s < end; ++s) {
      if (trial_.stages[s].observed.has_markers()) scored.push_back(s);
    }
    std::vector<Candidate> pool;
    for (std::size_t s = first; s < end; ++s) {
      if (end - first == 1 || !scored.empty()) pool.insert(pool.end(), candidates[s].begin(), candidates[s].end());
    }
    const Candidate* chosen = nullptr;
    double best = 0.0;
    for (const Candidate& c : pool) {
      double total = 0.0;
      for (std::size_t s : scored) total += misfit(s, *c.x);
      if (!chosen || total < best) {
        chosen = &c;
        best = total;
      }
    }
    for (std::size_t s = first; s < end; ++s) {
      StageFit stage;
      stage.id = trial_.stages[s].id;
      const Candidate* own = chosen;
      if (end - first > 1 && scored.empty()) {
        // No scan to choose by: each stage keeps its path equilibrium, as alone.
        own = candidates[s].empty() ? nullptr : &candidates[s].front();
      }
      if (own) {
        stage.x = *own->x;
        const double factor = model_->material().effects.relaxation_factor(ages_s_[s]);
        if (own->stage != s && factor != model_->material().effects.relaxation_factor(ages_s_[own->stage])) {
          model_->set_load_age_s(ages_s_[s]);
          const SolveReport r = statics_->solve(clamps_, stage_poses(static_cast<int>(s)), stage.x);
          fit.newton_iterations += r.iterations;
          if (!r.usable()) stage.x = candidates[s].empty() ? VecX() : *candidates[s].front().x;
        }
        fit.stages_from_scan += own->from_scan;
        fit.stages_sharing_an_equilibrium += end - first > 1 && own == chosen;
      }
      if (stage.x.size() == 0 && coarse_path) {
        // Neither tether found an equilibrium: follow the path on the twin itself, as before
        // (the Newton iterations spent so far stay counted).
        fit.stages_from_scan = 0;
        fit.stages_sharing_an_equilibrium = 0;
        return simulate_cold(fit, false);
      }
      if (stage.x.size() == 0) {
        fit.failure = simulated.failure.empty() ? fmt::format("stage {}: no equilibrium found", stage.id) : simulated.failure;
        return false;
      }
      fit.stages.push_back(std::move(stage));
    }
    first = end;
  }
  return true;
}

void TrialEvaluator::score(TrialFit& fit) const {
  std::vector<double> residuals;
  fit.residual_blocks.clear();
  // The sheet's quarters, split at the middle of its rest bounding box.
  Vec2 low = model_->mesh().rest_uv.front(), high = low;
  for (const Vec2& p : model_->mesh().rest_uv) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const Vec2 middle = 0.5 * (low + high);
  for (std::size_t s = 0; s < fit.stages.size(); ++s) {
    StageFit& stage = fit.stages[s];
    const StageObservation& observed = trial_.stages[s].observed;
    if (observed.has_markers()) {
      stage.nearest = nearest_vertex_error(observed.markers_m, stage.x);
      stage.predicted_markers_m = markers_->positions(stage.x);
      stage.correspondence = correspondence_error(observed.markers_m, stage.predicted_markers_m);
    } else {
      stage.nearest = nearest_vertex_error(observed.cloud_m, stage.x);
    }
    for (const Pairing& p : pairings(observed, *markers_, stage.x)) {
      const Vec3 r = p.predicted(stage.x) - p.observed;
      residuals.insert(residuals.end(), {r.x(), r.y(), r.z()});
      Vec2 uv = Vec2::Zero();
      for (int k = 0; k < 3; ++k) uv += p.weights(k) * model_->mesh().rest_uv[p.vertices[k]];
      const int block = 4 * static_cast<int>(s) + (uv.x() >= middle.x() ? 1 : 0) + (uv.y() >= middle.y() ? 2 : 0);
      fit.residual_blocks.insert(fit.residual_blocks.end(), 3, block);
    }
  }
  fit.residuals_m = Eigen::Map<const VecX>(residuals.data(), static_cast<Eigen::Index>(residuals.size()));
  fit.residual_count = static_cast<int>(residuals.size());
  fit.sum_squares_m2 = fit.residuals_m.squaredNorm();
}

void TrialEvaluator::differentiate(TrialFit& fit, const std::vector<MaterialParameter>& parameters,
                                   Derivatives derivatives) {
  const auto P = static_cast<Eigen::Index>(parameters.size());
  fit.coordinate_gradient = VecX::Zero(P);
  if (derivatives == Derivatives::kJacobian) fit.coordinate_jacobian.setZero(fit.residual_count, P);
  Eigen::Index row = 0;
  for (std::size_t s = 0; s < fit.stages.size(); ++s) {
    const StageFit& stage = fit.stages[s];
    const std::vector<Pairing> paired = pairings(trial_.stages[s].observed, *markers_, stage.x);
    if (paired.empty()) continue;
    // K and dg/dp of this stage's equilibrium: the model at this stage's load age.
    model_->set_load_age_s(ages_s_[s]);
    const DofMap dofs = model_->hold_clamps(clamps_, stage_poses(static_cast<int>(s)));
    auto& sensitivity = sensitivities_[s];
    if (!sensitivity) {
      sensitivity = std::make_unique<EquilibriumSensitivity>(*model_, dofs, stage.x);
    } else {
      sensitivity->update(stage.x);
    }
    // dS/dx = 2 sum r_o (d p_o / d x).
    VecX dS_dx = VecX::Zero(stage.x.size());
    for (const Pairing& p : paired) {
      const Vec3 r = p.predicted(stage.x) - p.observed;
      for (int k = 0; k < 3; ++k) dS_dx.segment<3>(3 * p.vertices[k]) += 2.0 * p.weights(k) * r;
    }
    fit.coordinate_gradient += sensitivity->coordinate_adjoint_gradient(dS_dx, parameters);
    if (derivatives == Derivatives::kJacobian) {
      const Eigen::MatrixXd tangents = sensitivity->coordinate_tangents(parameters);
      for (const Pairing& p : paired) {
        for (int k = 0; k < 3; ++k) {
          fit.coordinate_jacobian.middleRows(row, 3) += p.weights(k) * tangents.middleRows(3 * p.vertices[k], 3);
        }
        row += 3;
      }
    }
  }
}

TrialFit TrialEvaluator::evaluate(const Material& material, const std::vector<MaterialParameter>& parameters,
                                  Derivatives derivatives, bool fresh) {
  const auto start = std::chrono::steady_clock::now();
  TrialFit fit;
  auto finish = [&]() {
    fit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return fit;
  };
  // The trial's own density (measured: mass / area), unless the density is being identified.
  Material used = material;
  const bool density_varied = std::find(parameters.begin(), parameters.end(), MaterialParameter::kSurfaceDensity) != parameters.end();
  if (!density_varied && (trial_.mass_kg || trial_.surface_density_kg_m2)) {
    used.surface_density_kg_m2 = trial_.density_kg_m2(model_->mesh().total_rest_area());
  }
  try {
    model_->set_material(used);
  } catch (const std::exception& e) {
    fit.failure = e.what();
    return finish();
  }
  const VecX coordinates = search_coordinates(material, parameters);
  bool simulated = false;
  double start_sum_squares_m2 = 0.0;
  const ContinuationStarts starts = fresh ? ContinuationStarts{} : continuation_cached(coordinates);
  // From the nearest evaluation, and from the best fit within one material step when that is
  // another; the better continuation is kept.
  int newton_iterations = 0;
  for (const std::optional<std::size_t>& k : {starts.nearest, starts.best_nearby}) {
    if (!k) continue;
    TrialFit continued;
    const bool ok = simulate_warm(cache_[*k], used, parameters, continued);
    newton_iterations += continued.newton_iterations;
    if (!ok) continue;
    score(continued);
    if (!simulated || continued.sum_squares_m2 < fit.sum_squares_m2) {
      fit = std::move(continued);
      start_sum_squares_m2 = cache_[*k].sum_squares_m2;
      simulated = true;
    }
  }
  fit.newton_iterations = newton_iterations;
  fit.warm_started = simulated;
  if (!simulated) {
    if (!simulate_cold(fit)) {
      if (fit.failure.empty()) fit.failure = "the simulation did not converge";
      fit.stages.clear();
      return finish();
    }
    score(fit);
  }
  if (fit.warm_started && fit.sum_squares_m2 > kBranchCheckRatio * start_sum_squares_m2) {
    // Continued equilibria that fit far worse than those they started from may have been
    // carried onto a branch the scans would not choose (seen fitting marker mass and bending
    // together: L-BFGS then crept along a false valley). The material's fresh equilibria decide.
    TrialFit again = evaluate(material, parameters, derivatives, true);
    if (again.usable() && again.sum_squares_m2 < fit.sum_squares_m2) {
      again.newton_iterations += fit.newton_iterations;
      again.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return again;
    }
  }
  if (derivatives != Derivatives::kNone) {
    try {
      differentiate(fit, parameters, derivatives);
    } catch (const std::exception& e) {
      fit.failure = fmt::format("derivatives: {}", e.what());
      return finish();
    }
  }
  if (fresh) {
    // A fresh simulation that fits better than the equilibria continued to this material is on
    // a better branch: continuing from the old ones nearby would carry the worse one on.
    const ContinuationStarts continued = continuation_cached(coordinates);
    if (continued.nearest && fit.sum_squares_m2 < cache_[*continued.nearest].sum_squares_m2) cache_.clear();
  }
  CachedEquilibria entry{coordinates, fit.sum_squares_m2, {}};
  for (const StageFit& s : fit.stages) entry.stage_x.push_back(s.x);
  constexpr std::size_t kCacheSize = 16;
  if (cache_.size() == kCacheSize) cache_.erase(cache_.begin());
  cache_.push_back(std::move(entry));
  return finish();
}

}  // namespace twin
