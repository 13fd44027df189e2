// Rest state and frame indifference of the elastic terms (membrane + hinge bending):
//  - the flat sheet, placed anywhere with any rotation, feels no elastic force;
//  - a rigid motion x -> R x + t of any deformed state leaves each term's energy unchanged and
//    rotates its gradient (g -> R g per vertex), so the internal forces of membrane + bending
//    have zero resultant and zero moment (about any point, here the origin).
// The material is anisotropic (Y_u != Y_v, nu != 0, D_u != D_v) so that a wrong material frame
// or rest state cannot hide behind symmetry.

#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "tests/support/random_states.h"
#include "twin/model/clamp.h"
#include "twin/model/shell_model.h"

namespace twin::rest_state_test {
namespace {

constexpr double kEdge_m = 0.03;

Material anisotropic_material() {
  Material m;
  m.tensile_stiffness_u_N_m = 6000.0;
  m.tensile_stiffness_v_N_m = 2500.0;
  m.shear_stiffness_N_m = 800.0;
  m.poisson_ratio = 0.3;
  m.bending_rigidity_u_Nm = 2e-3;
  m.bending_rigidity_v_Nm = 7e-4;
  return m;
}

// Energy (J) and gradient (N, 3n) of one term.
double evaluate(const EnergyTerm& term, const VecX& x, VecX& grad) {
  grad = VecX::Zero(x.size());
  return term.evaluate(x, &grad, nullptr, HessianMode::kExact);
}

double largest_vertex_force(const VecX& f) {
  double m = 0.0;
  for (int i = 0; i < f.size() / 3; ++i) m = std::max(m, vertex(f, i).norm());
  return m;
}

// x -> R x + t per vertex.
VecX rigidly_moved(const VecX& x, const Mat3& r, const Vec3& t) {
  VecX y(x.size());
  for (int i = 0; i < x.size() / 3; ++i) vertex(y, i) = r * vertex(x, i) + t;
  return y;
}

TEST_CASE("the flat sheet feels no elastic force in any placement", "[twin][physics]") {
  const Material material = anisotropic_material();
  // Typical element forces: a membrane edge at unit strain, Y h (N), and a hinge at unit
  // angle, D / h (N).
  const double membrane_scale_N = material.tensile_stiffness_u_N_m * kEdge_m;
  const double bending_scale_N = material.bending_rigidity_u_Nm / kEdge_m;
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> offset(-2.0, 2.0);
  for (auto pattern : {TriangulationPattern::kOffsetRows, TriangulationPattern::kRightTriangles}) {
    const ShellModel model(make_rectangular_sheet(0.33, 0.21, kEdge_m, pattern), material);
    for (int trial = 0; trial < 4; ++trial) {
      SheetPlacement placement;
      placement.rotation = testing::random_rotation(rng);
      placement.origin_m = Vec3(offset(rng), offset(rng), offset(rng));
      const VecX x = place_flat(model.mesh(), placement);
      VecX g_membrane, g_bending;
      const double e_membrane = evaluate(model.membrane(), x, g_membrane);
      const double e_bending = evaluate(model.bending(), x, g_bending);
      INFO("pattern " << static_cast<int>(pattern) << ", trial " << trial);
      CHECK(largest_vertex_force(g_membrane) < 1e-12 * membrane_scale_N);
      CHECK(largest_vertex_force(g_bending) < 1e-12 * bending_scale_N);
      CHECK(e_membrane < 1e-20 * membrane_scale_N * kEdge_m);
      CHECK(e_bending < 1e-20 * bending_scale_N * kEdge_m);

      // The same measure sees small deformations: a 0.1 % stretch about the placement's
      // origin and a curvature of 1/m give forces far above the tolerances.
      VecX stretched = x;
      for (int i = 0; i < model.vertex_count(); ++i) {
        vertex(stretched, i) = placement.origin_m + 1.001 * (vertex(x, i) - placement.origin_m);
      }
      evaluate(model.membrane(), stretched, g_membrane);
      CHECK(largest_vertex_force(g_membrane) > 1e-5 * membrane_scale_N);
      const VecX bent = rigidly_moved(wrap_on_cylinder(model.mesh(), 0.4, 1.0),
                                      placement.rotation, placement.origin_m);
      evaluate(model.bending(), bent, g_bending);
      CHECK(largest_vertex_force(g_bending) > 1e-3 * bending_scale_N);
    }
  }
}

TEST_CASE("rigid motions leave elastic energies invariant and rotate their forces",
          "[twin][physics]") {
  const ShellModel model(make_rectangular_sheet(0.3, 0.2, kEdge_m), anisotropic_material());
  const int n = model.vertex_count();
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> offset(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    // Vertices moved by up to 15 % of an edge: strains and hinge angles of ~0.1-0.3.
    const VecX x = testing::random_deformed(model.mesh().rest_uv, kEdge_m, 0.15, rng);
    const Mat3 r = testing::random_rotation(rng);
    const Vec3 t(offset(rng), offset(rng), offset(rng));
    const VecX y = rigidly_moved(x, r, t);

    VecX total_force = VecX::Zero(3 * n);
    const std::vector<const EnergyTerm*> elastic = {&model.membrane(), &model.bending()};
    for (const EnergyTerm* term : elastic) {
      INFO(term->name() << ", trial " << trial);
      VecX gx, gy;
      const double ex = evaluate(*term, x, gx);
      const double ey = evaluate(*term, y, gy);
      REQUIRE(ex > 1e-6);  // J: the state is really deformed
      CHECK(std::abs(ey - ex) <= 1e-12 * ex);
      const VecX rotated = rigidly_moved(gx, r, Vec3::Zero());
      CHECK((gy - rotated).norm() <= 1e-12 * gx.norm());
      total_force -= gy;
    }

    // Internal forces of membrane + bending: no net force, no net moment about the origin.
    Vec3 net_force = Vec3::Zero(), net_torque = Vec3::Zero();
    double force_sum = 0.0, torque_sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const Vec3 f = vertex(total_force, i);
      net_force += f;
      net_torque += vertex(y, i).cross(f);
      force_sum += f.norm();
      torque_sum += vertex(y, i).norm() * f.norm();
    }
    INFO("trial " << trial << ": |sum f| " << net_force.norm() << " N of " << force_sum
                  << ", |sum x x f| " << net_torque.norm() << " N*m of " << torque_sum);
    CHECK(net_force.norm() <= 1e-12 * force_sum);
    CHECK(net_torque.norm() <= 1e-12 * torque_sum);
  }
}

}  // namespace
}  // namespace twin::rest_state_test
