#include "sim_hw/true_sheet.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

#include <omp.h>

#include "twin/trials/scenario.h"

namespace sim_hw {

TrueSheet::TrueSheet(const twin::SheetSpec& sheet, const twin::Material& material, const TrueSheetOptions& options)
    : physics_(make_true_sheet_physics(sheet, material, options)), placement_(sheet.placement) {
  const twin::SheetMesh& mesh = physics_->mesh();
  x_ = twin::VecX(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) x_.segment<3>(3 * i) = placement_.to_world(mesh.rest_uv[i]);
  v_ = twin::VecX::Zero(x_.size());
  published_x_ = x_;
}

namespace {

// The world is one physics thread next to the camera threads and the cell process on 2 shared
// cores: element loops run single-threaded here (an OpenMP team per step only adds waiting when
// the cores are busy). The setting is per thread, so each solving thread makes it.
void single_threaded_elements() { omp_set_num_threads(1); }

}  // namespace

twin::SolveReport TrueSheet::load(const std::vector<HeldGrasp>& grasps) {
  single_threaded_elements();
  const auto start = std::chrono::steady_clock::now();
  std::vector<twin::ClampSpec> specs;
  for (const HeldGrasp& g : grasps) specs.push_back(g.clamp);
  if (!physics_->clamps_compatible(specs)) throw std::runtime_error("initial load: two grasps hold one patch");
  std::vector<twin::ClampPose> held(grasps.size());
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    held[i].position_m = grasps[i].patch_pose.translation();
    held[i].rotation = grasps[i].patch_pose.linear();
  }
  // One static solve from the flat sheet with the patches at their holds: the operator hands the
  // ply over and lets it settle. A quasi-static continuation from the flat sheet's grasp points
  // took 10x longer (twin model, 2000 triangles: 24.8 s against about 2 s) for the same start.
  twin::VecX x(x_.size());
  const twin::SheetMesh& mesh = physics_->mesh();
  for (int i = 0; i < mesh.vertex_count(); ++i) x.segment<3>(3 * i) = placement_.to_world(mesh.rest_uv[i]);
  TrueSheetPhysics::Settled settled;
  try {
    settled = physics_->settle(specs, held, x);
  } catch (const std::invalid_argument& e) {
    settled.failure = e.what();
  }
  if (!settled.failure.empty()) {
    throw std::runtime_error("initial load: the hanging equilibrium was not found (" + settled.failure + ")");
  }
  twin::SolveReport report;
  report.status = twin::SolveStatus::kConverged;
  report.iterations = settled.iterations;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::lock_guard lock(mutex_);
  x_ = x;
  v_.setZero();
  published_x_ = x_;
  ++version_;
  grips_.clear();
  for (const HeldGrasp& g : grasps) grips_[g.clamp.id] = Grip{g.clamp, g.jaw_pose.inverse() * g.patch_pose, g.jaw_pose};
  grips_changed_ = true;
  return report;
}

bool TrueSheet::grip(const std::string& name, const Eigen::Isometry3d& jaw_pose, double capture_m,
                     double radius_m) {
  std::lock_guard lock(mutex_);
  if (grips_.count(name)) return true;
  const twin::Vec3 jaw = jaw_pose.translation();
  const twin::SheetMesh& mesh = physics_->mesh();
  int nearest = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const double d = (twin::vertex(published_x_, i) - jaw).norm();
    if (d < best) best = d, nearest = i;
  }
  if (nearest < 0 || best > capture_m) return false;  // closes on nothing
  twin::ClampSpec spec{name, mesh.rest_uv[nearest], radius_m};
  std::vector<twin::ClampSpec> specs = specs_locked();
  specs.push_back(spec);
  if (!physics_->clamps_compatible(specs)) return false;  // another gripper holds that patch
  grips_[name] = Grip{spec, jaw_pose.inverse() * physics_->patch_pose(spec, published_x_), jaw_pose};
  grips_changed_ = true;
  return true;
}

void TrueSheet::release(const std::string& name) {
  std::lock_guard lock(mutex_);
  if (grips_.erase(name)) grips_changed_ = true;
}

void TrueSheet::move_jaw(const std::string& name, const Eigen::Isometry3d& jaw_pose) {
  std::lock_guard lock(mutex_);
  const auto it = grips_.find(name);
  if (it != grips_.end()) it->second.jaw_pose = jaw_pose;
}

bool TrueSheet::holding(const std::string& name) const {
  std::lock_guard lock(mutex_);
  return grips_.count(name) > 0;
}

int TrueSheet::holding_count() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(grips_.size());
}

std::vector<twin::ClampSpec> TrueSheet::specs_locked() const {
  std::vector<twin::ClampSpec> specs;
  for (const auto& [name, g] : grips_) specs.push_back(g.clamp);
  return specs;
}

std::vector<twin::ClampPose> TrueSheet::poses_locked() const {
  std::vector<twin::ClampPose> poses;
  for (const auto& [name, g] : grips_) {
    const Eigen::Isometry3d patch = g.jaw_pose * g.patch_in_jaw;
    twin::ClampPose p;
    p.position_m = patch.translation();
    p.rotation = patch.linear();
    poses.push_back(p);
  }
  return poses;
}

void TrueSheet::step(double dt_s) {
  std::vector<twin::ClampSpec> specs;
  std::vector<twin::ClampPose> poses;
  bool changed = false;
  {
    std::lock_guard lock(mutex_);
    changed = grips_changed_;
    grips_changed_ = false;
    specs = specs_locked();
    poses = poses_locked();
    stats_.paused = specs.empty();
  }
  if (specs.empty()) return;
  single_threaded_elements();
  const auto start = std::chrono::steady_clock::now();
  std::string failure;
  try {
    failure = physics_->step(specs, poses, changed, dt_s, x_, v_);
  } catch (const std::invalid_argument& e) {
    failure = e.what();
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::lock_guard lock(mutex_);
  ++stats_.steps;
  stats_.last_step_ms = ms;
  stats_.max_step_ms = std::max(stats_.max_step_ms, ms);
  if (!failure.empty()) {
    ++stats_.failures;  // the state stays as it was (the physics leaves x, v unchanged)
    stats_.last_failure = failure;
    return;
  }
  stats_.last_substeps = physics_->last_substeps();
  published_x_ = x_;
  ++version_;
}

twin::VecX TrueSheet::positions() const {
  std::lock_guard lock(mutex_);
  return published_x_;
}

std::uint64_t TrueSheet::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

StepStats TrueSheet::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

double TrueSheet::sag_m() const {
  std::lock_guard lock(mutex_);
  const std::vector<twin::ClampPose> poses = poses_locked();
  if (poses.empty()) return 0.0;
  double mean_z = 0;
  for (const auto& p : poses) mean_z += p.position_m.z() / static_cast<double>(poses.size());
  double min_z = std::numeric_limits<double>::infinity();
  for (int i = 0; i < published_x_.size() / 3; ++i) min_z = std::min(min_z, published_x_[3 * i + 2]);
  return mean_z - min_z;
}

}  // namespace sim_hw
