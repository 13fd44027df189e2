#include "twin/bench/benchmark_sheet.h"

#include <cmath>

#include <stdexcept>
#include <string>

#include "twin/mesh/sheet_mesh.h"
#include "twin/solvers/implicit_stepper.h"
#include "twin/solvers/static_solver.h"

namespace twin::bench {

namespace {

Material benchmark_material() {
  Material material;
  material.name = "benchmark composite";
  material.surface_density_kg_m2 = 0.3;
  material.tensile_stiffness_u_N_m = material.tensile_stiffness_v_N_m = 5000.0;
  material.shear_stiffness_N_m = 5000.0;
  material.bending_rigidity_u_Nm = material.bending_rigidity_v_Nm = 1e-3;
  material.poisson_ratio = 0.3;
  material.tensile_viscosity_Ns_m = material.shear_viscosity_Ns_m = 5.0;
  return material;
}

const std::vector<ClampSpec>& clamp_specs() {
  static const std::vector<ClampSpec> specs = {{"A", Vec2(0.10, 0.05), 0.02},
                                               {"B", Vec2(kWidth_m - 0.05, 0.15), 0.02},
                                               {"C", Vec2(kWidth_m - 0.20, kHeight_m - 0.05), 0.02},
                                               {"D", Vec2(0.05, kHeight_m - 0.30), 0.02}};
  return specs;
}

}  // namespace

BenchmarkSheet::BenchmarkSheet(int target_triangles)
    : model(make_rectangular_sheet(kWidth_m, kHeight_m,
                                   edge_length_for_triangle_count(kWidth_m, kHeight_m, target_triangles)),
            benchmark_material()),
      clamps(model.mesh(), clamp_specs()) {
  SheetPlacement placement;
  placement.origin_m = Vec3(0.0, 0.0, 1.0);
  const Vec3 centre = placement.to_world(Vec2(kWidth_m / 2, kHeight_m / 2));
  poses.resize(clamp_specs().size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    poses[i].position_m = centre + 0.9 * (placement.to_world(clamp_specs()[i].material_point_m) - centre);
  }
  flat = place_flat(model.mesh(), placement);
}

std::vector<ClampPose> BenchmarkSheet::circling_poses(double t_s) const {
  std::vector<ClampPose> moving = poses;
  moving[0].position_m += 0.05 * Vec3(std::cos(M_PI * t_s) - 1.0, std::sin(M_PI * t_s), 0.0);
  return moving;
}

CirclingStates circling_states(const BenchmarkSheet& sheet, int steps, double dt_s) {
  VecX x = sheet.flat;
  StaticSolver statics(sheet.model);
  if (!statics.solve(sheet.clamps, sheet.poses, x).usable()) throw std::runtime_error("static equilibrium failed");
  CirclingStates states;
  ImplicitStepper stepper(sheet.model);
  VecX v = VecX::Zero(x.size());
  for (int s = 0; s <= steps; ++s) {
    states.x.push_back(x);
    states.v.push_back(v);
    if (s == steps) break;
    if (!stepper.step(x, v, dt_s, sheet.clamps, sheet.circling_poses((s + 1) * dt_s), linearized_step_options())
             .usable()) {
      throw std::runtime_error("step " + std::to_string(s) + " failed");
    }
  }
  return states;
}

}  // namespace twin::bench
