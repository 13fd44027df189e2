#pragma once
// Settled states of a sheet simulated by the fake world's independent physics (sim_hw
// true_sheet_physics.h: a plate on its own grid, no twin code), as the cell's tracker would
// report them on the twin's mesh: the true surface at each twin vertex's material point plus
// tracker noise. For the tests of what the cell learns: the twin is never scored on its own
// output here.
#include <random>
#include <vector>

#include "cell/learning/settled_state.h"
#include "sim_hw/true_sheet_physics.h"
#include "twin/mesh/material_point.h"
#include "twin/trials/grasp_plan.h"

namespace testing_support {

struct IndependentStates {
  twin::SheetMesh twin_mesh;
  twin::GraspPlan plan;
  std::vector<cell::learning::SettledObservation> states;
};

inline twin::Material lab_material(double tensile_N_m, double shear_N_m, double bending_Nm) {
  twin::Material m;
  m.name = "test sheet";
  m.surface_density_kg_m2 = 0.3;
  m.thickness_m = 0.0003;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = tensile_N_m;
  m.shear_stiffness_N_m = shear_N_m;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = bending_Nm;
  return m;
}

// A 0.6 x 0.5 m sheet held by three grasps through four states, the
// truth on a `grid_m` grid, the twin's mesh of about `twin_triangles` triangles, noise sigma_m.
// model: kTwin makes the states with the twin's own shell model on that grid instead (tests of the
// cell's plumbing on an effect the twin has, never of accuracy).
inline IndependentStates independent_states(const twin::Material& truth, int twin_triangles, double grid_m,
                                            double sigma_m, unsigned seed = 3,
                                            sim_hw::TruthModel model = sim_hw::TruthModel::kIndependent) {
  const double w = 0.6, h = 0.5;
  IndependentStates out;
  out.twin_mesh = twin::make_rectangular_sheet(w, h, twin::edge_length_for_triangle_count(w, h, twin_triangles));
  const std::vector<std::pair<std::string, twin::Vec2>> grasps = {
      {"A", {0.05, 0.05}}, {"B", {0.55, 0.06}}, {"C", {0.32, 0.46}}};
  const twin::Vec2 centre(0.3, 0.19);
  std::vector<twin::ClampSpec> specs;
  std::vector<twin::ClampPose> poses;
  for (const auto& [name, uv] : grasps) {
    twin::Grasp g;
    g.gripper = name;
    g.clamp = twin::ClampSpec{name, uv, 0.02};
    // Held 8 % closer to the middle than flat (slack), at 1 m.
    const twin::Vec2 held = centre + 0.92 * (uv - centre);
    g.hold_position_m = twin::Vec3(held.x(), held.y(), 1.0);
    out.plan.grasps.push_back(g);
    specs.push_back(g.clamp);
    twin::ClampPose p;
    p.position_m = g.hold_position_m;
    poses.push_back(p);
  }
  twin::SheetSpec sheet;
  sheet.mesh = twin::make_rectangular_sheet(w, h, grid_m);
  sim_hw::TrueSheetOptions options;
  options.grid_spacing_m = grid_m;
  options.model = model;
  auto physics = sim_hw::make_true_sheet_physics(sheet, truth, options);
  twin::SheetPlacement flat;
  flat.origin_m = twin::Vec3(0.0, 0.0, 1.0);
  twin::VecX x = twin::place_flat(physics->mesh(), flat);
  const twin::MaterialPointMap at_twin_vertices(physics->mesh(), out.twin_mesh.rest_uv);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_m);

  // The states: as loaded; C raised 10 cm and in; B 6 cm towards A; C raised 8 cm more.
  std::vector<std::vector<twin::ClampPose>> path = {poses};
  poses[2].position_m += twin::Vec3(0.0, -0.04, 0.10);
  path.push_back(poses);
  poses[1].position_m += twin::Vec3(-0.06, 0.0, 0.0);
  path.push_back(poses);
  poses[2].position_m += twin::Vec3(0.03, -0.03, 0.08);
  path.push_back(poses);

  std::vector<twin::ClampPose> at = path.front();
  double t = 0.0;
  for (const auto& target : path) {
    // Quasi-static, in five increments (a hanging sheet's equilibrium depends on the path).
    const std::vector<twin::ClampPose> from = at;
    for (int k = 1; k <= 5; ++k) {
      for (std::size_t g = 0; g < at.size(); ++g) at[g] = twin::interpolate(from[g], target[g], k / 5.0);
      const auto settled = physics->settle(specs, at, x);
      if (!settled.failure.empty()) throw std::runtime_error("independent sheet did not settle: " + settled.failure);
    }
    cell::learning::SettledObservation s;
    for (const auto& p : target) {
      s.grasp_positions_m.push_back(p.position_m);
      s.engaged.push_back(p.engaged ? 1 : 0);
    }
    for (twin::Vec3 p : at_twin_vertices.positions(x)) {
      s.vertices_m.push_back(p + twin::Vec3(noise(rng), noise(rng), noise(rng)));
    }
    s.cycle_noise_m = sigma_m;
    s.mean_noise_m = sigma_m;
    s.coverage = 1.0;
    s.cycles = 1;
    s.moved_at_s = t;
    s.time_s = t + 10.0;
    t += 20.0;
    out.states.push_back(std::move(s));
  }
  return out;
}

}  // namespace testing_support
