// The independent sheet against the continuum plate: cylinders bent along several directions,
// a sphere and a saddle (the coupling D12 a hinge model cannot set), pure twist (D66), and a
// cantilever under its own weight against Euler-Bernoulli.

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "sim_hw/real_sheet/equilibrium_solver.h"
#include "sim_hw/real_sheet/sheet_model.h"

namespace rs = sim_hw::real_sheet;

namespace {

rs::SheetMaterial laminate() {
  rs::SheetMaterial m;
  m.density_kg_m2 = 0.3;
  twin::Material t;
  t.tensile_stiffness_u_N_m = t.tensile_stiffness_v_N_m = 1e5;
  t.shear_stiffness_N_m = 4e4;
  m.membrane_C_N_m = rs::sheet_material_from(t).membrane_C_N_m;
  m.D11_Nm = 1.2e-3;
  m.D22_Nm = 0.5e-3;
  m.D12_Nm = 0.2e-3;
  m.D66_Nm = 0.3e-3;
  return m;
}

// Bending energy alone (J): the model's energy less gravity, with no membrane.
double bending_energy(const rs::SheetModel& model, const Eigen::VectorXd& x) {
  double gravity = 0;
  for (int i = 0; i < model.node_count(); ++i) gravity += model.node_mass_kg()[i] * rs::kGravity_m_s2 * x[3 * i + 2];
  return model.energy(x, {}, nullptr, nullptr, rs::Hessian::kExact) - gravity;
}

rs::SheetMaterial without_membrane(rs::SheetMaterial m) {
  m.membrane_C_N_m.setZero();
  return m;
}

// Continuum energy density 1/2 k^T D k, k = (k_uu, k_vv, 2 k_uv).
double plate_density(const rs::SheetMaterial& m, double kuu, double kvv, double kuv) {
  const Eigen::Vector3d k(kuu, kvv, 2 * kuv);
  return 0.5 * k.dot(m.bending_D_Nm() * k);
}

}  // namespace

TEST_CASE("real sheet: a cylinder along any direction has the plate's bending energy", "[real_sheet]") {
  const rs::SheetMaterial m = without_membrane(laminate());
  const double W = 0.4, H = 0.3, R = 0.25;
  for (const double spacing : {0.02, 0.01}) {
    const rs::Grid grid(W, H, spacing);
    const rs::SheetModel model(grid, m);
    for (const double deg : {0.0, 30.0, 45.0, 90.0, 135.0}) {
      const double th = deg * std::numbers::pi / 180, c = std::cos(th), s = std::sin(th);
      Eigen::VectorXd x(3 * grid.node_count());
      for (int n = 0; n < grid.node_count(); ++n) {
        const rs::Vec2 uv = grid.rest_uv(n);
        const double along = c * uv.x() + s * uv.y(), across = -s * uv.x() + c * uv.y();
        x.segment<3>(3 * n) = rs::Vec3(c, s, 0) * R * std::sin(along / R) + rs::Vec3(-s, c, 0) * across +
                              rs::Vec3(0, 0, R * (1 - std::cos(along / R)));
      }
      const double expected = W * H * plate_density(m, c * c / R, s * s / R, c * s / R);
      INFO("spacing " << spacing << " m, cylinder at " << deg << " deg");
      CHECK(bending_energy(model, x) == Approx(expected).epsilon(spacing < 0.015 ? 0.002 : 0.01));
    }
  }
}

TEST_CASE("real sheet: a sphere, a saddle and a pure twist cost what the plate says", "[real_sheet]") {
  const rs::SheetMaterial m = without_membrane(laminate());
  const double W = 0.3, H = 0.3, k = 0.05;  // shallow, so the graph's curvature is the plate's
  const rs::Grid grid(W, H, 0.01);
  const rs::SheetModel model(grid, m);
  const auto energy_of = [&](double kuu, double kvv, double kuv) {
    Eigen::VectorXd x(3 * grid.node_count());
    for (int n = 0; n < grid.node_count(); ++n) {
      const double u = grid.rest_uv(n).x() - W / 2, v = grid.rest_uv(n).y() - H / 2;
      x.segment<3>(3 * n) = rs::Vec3(u, v, 0.5 * kuu * u * u + kuv * u * v + 0.5 * kvv * v * v);
    }
    return bending_energy(model, x);
  };
  const double area = W * H;
  CHECK(energy_of(k, k, 0) == Approx(area * plate_density(m, k, k, 0)).epsilon(0.002));
  CHECK(energy_of(k, -k, 0) == Approx(area * plate_density(m, k, -k, 0)).epsilon(0.002));
  CHECK(energy_of(0, 0, k) == Approx(area * plate_density(m, 0, 0, k)).epsilon(0.002));
  // The sphere and the saddle differ by the coupling: 2 D12 k^2 per unit area.
  CHECK(energy_of(k, k, 0) - energy_of(k, -k, 0) == Approx(area * 2 * m.D12_Nm * k * k).epsilon(0.005));
}

TEST_CASE("real sheet: a cantilever under its own weight bends as Euler-Bernoulli says", "[real_sheet]") {
  rs::SheetMaterial m = laminate();
  m.D11_Nm = m.D22_Nm = 1.0;  // stiff, so the tip moves about 1 % of the length (linear range)
  m.D12_Nm = 0.0;             // nu = 0: a strip's and a plate's rigidity agree
  m.D66_Nm = 0.5;
  const double L = 0.3, b = 0.03;
  const double q = m.density_kg_m2 * b * rs::kGravity_m_s2;  // N/m
  const double expected = -q * std::pow(L, 4) / (8 * m.D11_Nm * b);
  // Clamped: tiny stiff pads on every node of the first two columns, which holds the beam from
  // somewhere between them: an O(h) uncertainty of the length that refinement must remove.
  const auto tip_deflection = [&](double spacing) {
    const rs::Grid grid(L, b, spacing);
    const rs::SheetModel model(grid, m);
    std::vector<rs::JawHold> jaws;
    rs::JawPadOptions o;
    o.grip_radius_m = 0;
    o.pad_stiffness_N_m3 = 1e14;
    for (int j = 0; j < grid.nv(); ++j) {
      for (int i = 0; i < 2; ++i) {
        rs::JawHold h;
        h.pad = rs::make_jaw_pad(grid, "root", grid.rest_uv(grid.node(i, j)), rs::JawKind::kRigid, o);
        h.centre_m = rs::Vec3(grid.rest_uv(grid.node(i, j)).x(), grid.rest_uv(grid.node(i, j)).y(), 0);
        jaws.push_back(h);
      }
    }
    Eigen::VectorXd x = grid.flat_positions();
    const rs::EquilibriumReport report = rs::solve_equilibrium(model, x, jaws);
    INFO(report.message);
    REQUIRE(report.converged);
    double tip = 0;
    for (int j = 0; j < grid.nv(); ++j) tip += x[3 * grid.node(grid.nu() - 1, j) + 2] / grid.nv();
    return tip;
  };
  const double coarse = tip_deflection(0.01), fine = tip_deflection(0.005), finer = tip_deflection(0.0025);
  INFO("tip " << coarse << " / " << fine << " / " << finer << " m, Euler-Bernoulli " << expected << " m");
  CHECK(std::abs(finer - expected) < 0.6 * std::abs(fine - expected));
  CHECK(std::abs(fine - expected) < 0.6 * std::abs(coarse - expected));
  // First order (the clamp's place): the error halves with the spacing, and the extrapolation
  // to zero spacing lands on the beam.
  CHECK(2 * finer - fine == Approx(expected).epsilon(0.005));
  CHECK(finer == Approx(expected).epsilon(0.04));
}
