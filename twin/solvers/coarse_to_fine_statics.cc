#include "twin/solvers/coarse_to_fine_statics.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

namespace twin {

VecX interpolate_positions(const MaterialPointMap& to_vertices, const VecX& x) {
  VecX out(3 * static_cast<Eigen::Index>(to_vertices.size()));
  for (int i = 0; i < to_vertices.size(); ++i) out.segment<3>(3 * i) = to_vertices.location(i).position(x);
  return out;
}

// One coarse mesh with its own model, clamps and solver, and the maps to and from the levels
// around it.
struct CoarseToFineStatics::Level {
  std::unique_ptr<ShellModel> model;
  std::unique_ptr<ClampSet> clamps;
  std::unique_ptr<StaticSolver> statics;
  // Where this level starts: its vertices on the fine mesh (the caller's start seen here).
  std::unique_ptr<MaterialPointMap> from_fine;
  // The next finer level's vertices (the fine mesh's for the last level) on this mesh.
  std::unique_ptr<MaterialPointMap> to_finer;
  std::vector<Vec2> marker_uv_m;  // the fine model's markers, in material coordinates
};

namespace {

std::vector<ClampSpec> specs_of(const ClampSet& clamps) {
  std::vector<ClampSpec> specs;
  for (int i = 0; i < clamps.size(); ++i) specs.push_back(clamps[i].spec());
  return specs;
}

std::vector<Vec2> marker_uv(const ShellModel& model) {
  std::vector<Vec2> uv;
  for (const MaterialPointLocation& m : model.marker_points()) {
    Vec2 p = Vec2::Zero();
    for (int k = 0; k < 3; ++k) p += m.weights(k) * model.mesh().rest_uv[m.vertices[k]];
    uv.push_back(p);
  }
  return uv;
}

}  // namespace

CoarseToFineStatics::CoarseToFineStatics(const ShellModel& fine, const ClampSet& fine_clamps,
                                         std::vector<SheetMesh> coarse_meshes)
    : fine_(fine), fine_clamps_(fine_clamps), fine_statics_(fine) {
  std::sort(coarse_meshes.begin(), coarse_meshes.end(),
            [](const SheetMesh& a, const SheetMesh& b) { return a.triangle_count() > b.triangle_count(); });
  // Finest first while building: each level must be well under the one above it.
  std::vector<SheetMesh> kept;
  int finer_triangles = fine.mesh().triangle_count();
  for (SheetMesh& mesh : coarse_meshes) {
    if (3 * mesh.triangle_count() >= 2 * finer_triangles) continue;
    finer_triangles = mesh.triangle_count();
    kept.push_back(std::move(mesh));
  }
  const std::vector<ClampSpec> specs = specs_of(fine_clamps);
  const std::vector<Vec2> markers = marker_uv(fine);
  const SheetMesh* finer = &fine.mesh();
  std::vector<std::unique_ptr<Level>> built;
  for (SheetMesh& mesh : kept) {
    const std::string name = "coarse mesh of " + std::to_string(mesh.triangle_count()) + " triangles";
    auto level = std::make_unique<Level>();
    try {
      level->model = std::make_unique<ShellModel>(std::move(mesh), fine.material());
      level->clamps = std::make_unique<ClampSet>(level->model->mesh(), specs);
      level->to_finer = std::make_unique<MaterialPointMap>(level->model->mesh(), finer->rest_uv);
      level->from_fine = std::make_unique<MaterialPointMap>(fine.mesh(), level->model->mesh().rest_uv);
      if (!markers.empty()) level->model->set_marker_points(MaterialPointMap(level->model->mesh(), markers));
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument(name + ": " + error.what());
    }
    if (fine.clamp_grip().clamp_count() > 0) level->model->set_clamp_grips(*level->clamps);
    if (fine.clamp_slip().has_clamps()) level->model->set_clamp_slips(*level->clamps);
    level->statics = std::make_unique<StaticSolver>(*level->model);
    level->marker_uv_m = markers;
    finer = &level->model->mesh();
    built.push_back(std::move(level));
  }
  std::reverse(built.begin(), built.end());
  levels_ = std::move(built);
}

CoarseToFineStatics::~CoarseToFineStatics() = default;

void CoarseToFineStatics::sync_level(Level& level) const {
  level.model->set_material(fine_.material());
  level.model->set_load_age_s(fine_.load_age_s());  // free when the stiffness factor is the same
}

CoarseToFineReport CoarseToFineStatics::solve(const std::vector<ClampPose>& poses, VecX& x,
                                              const NewtonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CoarseToFineReport report;
  report.total.status = SolveStatus::kMaxIterations;
  // x on the finer level being built up; empty until a level has solved.
  VecX carried;
  const MaterialPointMap* carry_map = nullptr;  // carried's vertices -> next finer level
  for (const std::unique_ptr<Level>& level : levels_) {
    sync_level(*level);
    VecX lx;
    SolveReport r;
    if (carried.size() > 0) {
      lx = interpolate_positions(*carry_map, carried);
      r = level->statics->solve(*level->clamps, poses, lx, options, StaticSolver::OnFailure::kGiveUp);
    }
    if (!r.usable()) {
      // The coarsest level, or a coarser equilibrium that does not carry over (a wrinkle this
      // mesh cannot hold): from the caller's start, settling if need be.
      lx = interpolate_positions(*level->from_fine, x);
      r.append(level->statics->solve(*level->clamps, poses, lx, options));
    }
    report.levels.push_back(r);
    report.level_triangles.push_back(level->model->mesh().triangle_count());
    report.total.iterations += r.iterations;
    report.total.factorizations += r.factorizations;
    if (r.usable()) {
      carried = std::move(lx);
      carry_map = level->to_finer.get();
    } else {
      carried.resize(0);
    }
  }
  SolveReport fine_report;
  VecX fx = x;
  if (carried.size() > 0) {
    fx = interpolate_positions(*carry_map, carried);
    fine_report = fine_statics_.solve(fine_clamps_, poses, fx, options, StaticSolver::OnFailure::kGiveUp);
  }
  if (!fine_report.usable()) {
    report.fell_back = !levels_.empty();
    fx = x;
    fine_report.append(fine_statics_.solve(fine_clamps_, poses, fx, options));
  }
  report.levels.push_back(fine_report);
  report.level_triangles.push_back(fine_.mesh().triangle_count());
  report.total.iterations += fine_report.iterations;
  report.total.factorizations += fine_report.factorizations;
  report.total.fallbacks = report.fell_back ? 1 : 0;
  report.total.status = fine_report.status;
  report.total.residual = fine_report.residual;
  report.total.energy_J = fine_report.energy_J;
  report.total.message = fine_report.message;
  report.total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (fine_report.usable()) x.swap(fx);
  return report;
}

}  // namespace twin
