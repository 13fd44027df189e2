#include "cell/cell_twin.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

namespace cell {

CellTwin::CellTwin(const twin::SheetMesh& mesh, const twin::Material& material,
                   const twin::GraspPlan& plan, const twin::SheetPlacement& placement)
    : model_(std::make_unique<twin::ShellModel>(mesh, material)),
      clamps_(model_->mesh(), plan.clamp_specs()),
      poses_(plan.grasps.size()),
      step_options_(twin::background_linearized_step_options()) {
  x_ = twin::place_flat(model_->mesh(), placement);
  v_ = twin::VecX::Zero(x_.size());
  // The jaws close on the flat ply, so each clamp holds its patch turned as the ply lies.
  for (auto& p : poses_) p.rotation = placement.rotation;
  jaw_rotation_ = placement.rotation;
  // Only for the clamp effects the material has (model_effects.h): grip springs' couplings to a
  // released clamp's host triangle would otherwise fill in every factorisation for nothing.
  model_->set_clamps_of_material_effects(clamps_);
  statics_ = std::make_unique<twin::StaticSolver>(*model_);
  stepper_ = std::make_unique<twin::ImplicitStepper>(*model_);
}

void CellTwin::set_positions(const std::vector<twin::Vec3>& grasp_positions_m) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < poses_.size() && i < grasp_positions_m.size(); ++i) {
    poses_[i].position_m = poisoned_ ? twin::Vec3(nan, nan, nan) : grasp_positions_m[i];
  }
}

std::string CellTwin::initialise(const std::vector<twin::Vec3>& grasp_positions_m) {
  if (grasp_positions_m.size() != poses_.size()) return "grasp positions do not match the plan";
  set_positions(grasp_positions_m);
  twin::VecX x = x_;
  const twin::SolveReport r = statics_->solve(clamps_, poses_, x);
  if (!r.usable()) return "static equilibrium failed: " + r.brief();
  if (!x.allFinite()) return "static equilibrium is not finite";
  x_ = x;
  v_.setZero();
  // A new stepper: the clamps start from where the equilibrium holds them.
  stepper_ = std::make_unique<twin::ImplicitStepper>(*model_);
  initialised_ = true;
  return "";
}

std::string CellTwin::set_material(const twin::Material& material, const std::vector<twin::Vec3>& grasp_positions_m) {
  const twin::Material old = model_->material();
  try {
    model_->set_material(material);
  } catch (const std::exception& e) {  // e.g. another bending model: the solvers keep their terms
    return std::string("material not taken: ") + e.what();
  }
  model_->set_clamps_of_material_effects(clamps_);
  statics_ = std::make_unique<twin::StaticSolver>(*model_);
  const std::string problem = initialise(grasp_positions_m);
  if (!problem.empty()) {
    model_->set_material(old);
    model_->set_clamps_of_material_effects(clamps_);
    statics_ = std::make_unique<twin::StaticSolver>(*model_);
    stepper_ = std::make_unique<twin::ImplicitStepper>(*model_);
  }
  return problem;
}

void CellTwin::adopt_state(const twin::VecX& x) {
  if (x.size() != x_.size() || !x.allFinite()) return;
  x_ = x;
  v_.setZero();
  stepper_ = std::make_unique<twin::ImplicitStepper>(*model_);
}

TwinStepResult CellTwin::step(double dt_s, const std::vector<twin::Vec3>& grasp_positions_m) {
  TwinStepResult result;
  if (!initialised_) {
    result.message = "twin not initialised";
    return result;
  }
  if (grasp_positions_m.size() != poses_.size()) {
    result.message = "grasp positions do not match the plan";
    return result;
  }
  set_positions(grasp_positions_m);
  const auto t0 = std::chrono::steady_clock::now();
  twin::VecX x = x_, v = v_;
  twin::SolveReport r;
  try {
    r = stepper_->step(x, v, dt_s, clamps_, poses_, step_options_);
  } catch (const std::exception& e) {  // the cycle must not throw (e.g. out of memory)
    result.message = std::string("twin step threw: ") + e.what();
    return result;
  }
  if (const int stall = stall_ms_; stall > 0) std::this_thread::sleep_for(std::chrono::milliseconds(stall));
  result.step_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  result.substeps = stepper_->last_substeps();
  result.iterations = r.iterations;
  if (!r.usable()) {
    result.message = "twin step failed: " + r.brief();
  } else if (!x.allFinite() || !v.allFinite()) {
    result.message = "twin step gave non-finite positions";
  } else {
    x_ = std::move(x);
    v_ = std::move(v);
    result.ok = true;
  }
  return result;
}

void CellTwin::set_background_factorization(bool on) {
  step_options_ = on ? twin::background_linearized_step_options() : twin::linearized_step_options();
}

void CellTwin::release(int grasp) { poses_[grasp].engaged = false; }

twin::SheetPlacement placement_under_grasps(const twin::GraspPlan& plan) {
  twin::Vec2 uv = twin::Vec2::Zero();
  twin::Vec3 hold = twin::Vec3::Zero();
  for (const auto& g : plan.grasps) {
    uv += g.clamp.material_point_m;
    hold += g.hold_position_m;
  }
  const double n = static_cast<double>(plan.grasps.size());
  twin::SheetPlacement p;
  p.origin_m = hold / n - twin::Vec3(uv.x() / n, uv.y() / n, 0.0);
  return p;
}

}  // namespace cell
