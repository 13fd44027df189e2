// The independent sheet's solver and stage path: equilibria balance the weight, a pivot lets
// the sheet hang with its centre of mass below the pivot, a failed solve leaves the state as it
// was, and the lab's stage path reaches every stage of a clamp protocol.

#include <cmath>

#include <catch2/catch.hpp>

#include "sim_hw/real_sheet/equilibrium_solver.h"
#include "sim_hw/real_sheet/stage_path.h"

namespace rs = sim_hw::real_sheet;

namespace {

twin::Material cloth() {
  twin::Material m;
  m.surface_density_kg_m2 = 0.11;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 2000;
  m.shear_stiffness_N_m = 300;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 2e-4;
  return m;
}

rs::JawHold jaw_at(const rs::Grid& grid, const rs::Vec2& uv, rs::JawKind kind, double radius = 0.015) {
  rs::JawPadOptions o;
  o.grip_radius_m = radius;
  rs::JawHold h;
  h.pad = rs::make_jaw_pad(grid, "J", uv, kind, o);
  h.centre_m = rs::Vec3(uv.x(), uv.y(), 0.0);
  return h;
}

rs::Vec3 centre_of_mass(const rs::SheetModel& model, const Eigen::VectorXd& x) {
  rs::Vec3 c = rs::Vec3::Zero();
  for (int i = 0; i < model.node_count(); ++i) c += model.node_mass_kg()[i] * x.segment<3>(3 * i);
  return c / model.node_mass_kg().sum();
}

}  // namespace

TEST_CASE("real sheet: a sheet hanging from two jaws is in equilibrium with its weight", "[real_sheet]") {
  const rs::Grid grid(0.3, 0.25, 0.025);
  const rs::SheetModel model(grid, rs::sheet_material_from(cloth()));
  std::vector<rs::JawHold> jaws = {jaw_at(grid, rs::Vec2(0.03, 0.22), rs::JawKind::kRigid),
                                   jaw_at(grid, rs::Vec2(0.27, 0.22), rs::JawKind::kRigid)};
  jaws[1].centre_m.x() -= 0.02;  // a little slack
  Eigen::VectorXd x = grid.flat_positions();
  rs::EquilibriumOptions o;
  o.initial_damping_1_s2 = 1e4;
  const rs::EquilibriumReport report = rs::solve_equilibrium(model, x, jaws, o);
  INFO(report.message);
  REQUIRE(report.converged);
  // The jaws carry the weight: the pads' vertical pull sums to it.
  Eigen::VectorXd g;
  model.energy(x, jaws, &g, nullptr, rs::Hessian::kExact);
  CHECK(g.norm() < 1e-6);
  double lowest = 0;
  for (int i = 0; i < model.node_count(); ++i) lowest = std::min(lowest, x[3 * i + 2]);
  CHECK(lowest < -0.1);  // it hangs
  double pull = 0;
  for (const rs::JawHold& j : jaws) {
    for (const rs::JawSample& s : j.pad.samples) {
      pull += s.stiffness_N_m * (j.centre_m + j.rotation * s.offset_m - model.grid().position(x, s.at)).z();
    }
  }
  CHECK(pull == Approx(model.total_weight_N()).epsilon(1e-6));
}

TEST_CASE("real sheet: a pivot jaw lets the sheet hang with its centre of mass below it", "[real_sheet]") {
  const rs::Grid grid(0.3, 0.25, 0.025);
  const rs::SheetModel model(grid, rs::sheet_material_from(cloth()));
  for (const rs::JawKind kind : {rs::JawKind::kPivot, rs::JawKind::kRigid}) {
    std::vector<rs::JawHold> jaws = {jaw_at(grid, rs::Vec2(0.05, 0.2), kind)};
    Eigen::VectorXd x = grid.flat_positions();
    rs::EquilibriumOptions o;
    o.initial_damping_1_s2 = 1e4;
    o.max_iterations = 2000;
    const rs::EquilibriumReport report = rs::solve_equilibrium(model, x, jaws, o);
    INFO(report.message);
    REQUIRE(report.converged);
    const rs::Vec3 c = centre_of_mass(model, x);
    const double off_axis = (c - jaws[0].centre_m).head<2>().norm();
    if (kind == rs::JawKind::kPivot) {
      CHECK(off_axis < 1e-4);
      CHECK(!jaws[0].rotation.isIdentity(1e-3));  // the jaw turned
    } else {
      CHECK(off_axis > 0.01);  // rigid jaws hold the sheet's edge level: it hangs to one side
    }
  }
}

TEST_CASE("real sheet: a solve that cannot converge leaves the state as it was", "[real_sheet]") {
  const rs::Grid grid(0.3, 0.25, 0.05);
  const rs::SheetModel model(grid, rs::sheet_material_from(cloth()));
  std::vector<rs::JawHold> jaws = {jaw_at(grid, rs::Vec2(0.05, 0.2), rs::JawKind::kPivot)};
  Eigen::VectorXd x = grid.flat_positions();
  const Eigen::VectorXd before = x;
  rs::EquilibriumOptions o;
  o.max_iterations = 2;
  const rs::EquilibriumReport report = rs::solve_equilibrium(model, x, jaws, o);
  CHECK_FALSE(report.converged);
  CHECK(!report.message.empty());
  CHECK(x == before);
  CHECK(jaws[0].rotation.isIdentity(0.0));
}

TEST_CASE("real sheet: the stage path follows a clamp protocol through a release", "[real_sheet]") {
  rs::SheetModel model(rs::Grid(0.6, 0.6, 0.03), rs::sheet_material_from(cloth()));
  const std::vector<twin::ClampSpec> clamps = {{"A", twin::Vec2(0.1, 0.02), 0.015},
                                               {"B", twin::Vec2(0.58, 0.2), 0.015},
                                               {"C", twin::Vec2(0.45, 0.58), 0.015},
                                               {"D", twin::Vec2(0.02, 0.4), 0.015}};
  std::vector<rs::PathStage> stages(3);
  // Stage 1: slack and level, 1 m up; 2: C raised; 3: D let go.
  for (std::size_t c = 0; c < clamps.size(); ++c) {
    const twin::Vec2 p = clamps[c].material_point_m - twin::Vec2(0.3, 0.3);
    stages[0].poses.push_back({twin::Vec3(0.95 * p.x(), 0.95 * p.y(), 1.0), twin::Mat3::Identity(), true});
  }
  stages[1].poses = stages[0].poses;
  stages[1].poses[2].position_m.z() += 0.15;
  stages[2].poses = stages[1].poses;
  stages[2].poses[3].engaged = false;
  const rs::PathResult result = rs::simulate_path(model, clamps, stages);
  INFO(result.failure);
  REQUIRE(result.usable());
  REQUIRE(result.stages.size() == 3);
  // Each stage holds the jaws where the protocol put them.
  const rs::Grid& grid = model.grid();
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t c = 0; c < clamps.size(); ++c) {
      if (!stages[k].poses[c].engaged) continue;
      const rs::Vec3 at = grid.position(result.stages[k], grid.locate(clamps[c].material_point_m));
      CHECK((at - stages[k].poses[c].position_m).norm() < 1e-4);
    }
  }
  // The released corner falls.
  const rs::Vec3 d2 = grid.position(result.stages[1], grid.locate(clamps[3].material_point_m));
  const rs::Vec3 d3 = grid.position(result.stages[2], grid.locate(clamps[3].material_point_m));
  CHECK(d3.z() < d2.z() - 0.05);
}
