// The hidden effects of the blind sets in the independent sheet's own forms
// (sim_hw/real_sheet/sheet_material.h): each present when the material file asks for it, absent
// otherwise, and with the size the material says.

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "sim_hw/real_sheet/jaw_pad.h"
#include "sim_hw/real_sheet/sheet_material.h"
#include "sim_hw/real_sheet/sheet_model.h"

namespace rs = sim_hw::real_sheet;

TEST_CASE("real sheet: a material file's effects map onto the model's own forms", "[real_sheet]") {
  twin::Material m;
  m.poisson_ratio = 0.3;
  m.bending_rigidity_u_Nm = 4e-4;
  m.bending_rigidity_v_Nm = 1e-4;
  const rs::SheetMaterial plain = rs::sheet_material_from(m);
  // Huber's orthotropic plate: D12 + 2 D66 = sqrt(D11 D22).
  CHECK(plain.D11_Nm == 4e-4);
  CHECK(plain.D22_Nm == 1e-4);
  CHECK(plain.D12_Nm + 2 * plain.D66_Nm == Approx(2e-4));
  CHECK(plain.creep_factor(300) == 1.0);
  CHECK(plain.pad_strength == 0.0);
  CHECK(plain.slip_compliance_m_N == 0.0);

  m.effects.relaxation_fraction = 0.4;
  m.effects.relaxation_time_s = 100;
  m.effects.clamp_grip_strength = 0.8;
  m.effects.clamp_grip_width_m = 0.03;
  m.effects.clamp_slip_compliance_m_N = 5e-4;
  m.effects.rest_curvature_uu_1_m = 0.5;
  m.effects.rest_curvature_uv_1_m = -0.2;
  const rs::SheetMaterial e = rs::sheet_material_from(m);
  // Creep: no loss at age 0, the long-term loss (1 - f) long after, a retardation curve between.
  CHECK(e.creep_factor(0) == 1.0);
  CHECK(e.creep_factor(std::numeric_limits<double>::quiet_NaN()) == Approx(0.6));
  CHECK(e.creep_factor(1e6) == Approx(0.6));
  const double f_tau = 1.0 / (1.0 + (0.4 / 0.6) * (1.0 - std::exp(-1.0)));
  CHECK(e.creep_factor(100) == Approx(f_tau));
  CHECK(e.pad_extension_m == 0.03);
  CHECK(e.pad_strength == 0.8);
  const Eigen::Vector3d k0 = rs::rest_curvature_at(e, rs::Vec2(0.3, 0.2));
  CHECK(k0[0] == 0.5);
  CHECK(k0[2] == Approx(-0.4));  // 2 k_uv
}

TEST_CASE("real sheet: wide and slipping jaws hold as the material says", "[real_sheet]") {
  const rs::Grid grid(0.4, 0.3, 0.02);
  rs::JawPadOptions o;
  o.grip_radius_m = 0.015;
  const rs::JawPad rigid = rs::make_jaw_pad(grid, "A", rs::Vec2(0.2, 0.15), rs::JawKind::kRigid, o);
  double area = 0, reach = 0;
  for (const rs::JawSample& s : rigid.samples) area += s.area_m2, reach = std::max(reach, s.offset_m.norm());
  CHECK(area == Approx(std::numbers::pi * 0.015 * 0.015).epsilon(1e-9));
  CHECK(reach < 0.015);
  CHECK(rigid.tangential_share == 1.0);

  o.extension_m = 0.03;
  o.extension_strength = 0.5;
  o.slip_compliance_m_N = 1e-3;
  const rs::JawPad wide = rs::make_jaw_pad(grid, "A", rs::Vec2(0.2, 0.15), rs::JawKind::kRigid, o);
  double hold_N_m = 0, beyond = 0;
  for (const rs::JawSample& s : wide.samples) {
    hold_N_m += s.stiffness_N_m;
    if (s.offset_m.norm() > 0.015) beyond = std::max(beyond, s.offset_m.norm());
  }
  CHECK(beyond > 0.04);   // the pads hold out to the radius plus the extension
  CHECK(beyond < 0.045);
  // Slip: the whole pad gives 1 mm per newton along its faces.
  CHECK(1.0 / (wide.tangential_share * hold_N_m) == Approx(1e-3));
}

TEST_CASE("real sheet: a crease rests the sheet at its angle along a band across its line", "[real_sheet]") {
  rs::SheetMaterial m;
  m.creases.push_back({rs::Vec2(0.2, 0.1), 0.5, 0.9, 0.015});  // through (0.2, 0.1), 0.5 rad from u, 0.9 rad fold
  const rs::Vec2 t(std::cos(0.5), std::sin(0.5)), n(-t.y(), t.x());
  // The rest curvature across the line integrates to the fold angle; along it, none; off the band, none.
  double across = 0;
  const int steps = 2000;
  for (int k = 0; k < steps; ++k) {
    const double d = -0.01 + 0.02 * (k + 0.5) / steps;
    const Eigen::Vector3d kr = rs::rest_curvature_at(m, rs::Vec2(0.2, 0.1) + d * n);
    const Eigen::Matrix2d K = (Eigen::Matrix2d() << kr[0], kr[2] / 2, kr[2] / 2, kr[1]).finished();
    across += n.dot(K * n) * 0.02 / steps;
    CHECK(std::abs(t.dot(K * t)) < 1e-9);
  }
  CHECK(across == Approx(0.9).epsilon(1e-4));
  CHECK(rs::rest_curvature_at(m, rs::Vec2(0.2, 0.1) + 0.02 * n).norm() == 0.0);
}

TEST_CASE("real sheet: marker masses add to the sheet's weight", "[real_sheet]") {
  rs::SheetMaterial m;
  m.density_kg_m2 = 0.3;
  m.marker_mass_kg = 2e-3;
  const rs::Grid grid(0.4, 0.3, 0.02);
  const rs::SheetModel with(grid, m, {rs::Vec2(0.1, 0.1), rs::Vec2(0.33, 0.21)});
  m.marker_mass_kg = 0;
  const rs::SheetModel without(grid, m, {rs::Vec2(0.1, 0.1), rs::Vec2(0.33, 0.21)});
  CHECK(without.node_mass_kg().sum() == Approx(0.3 * 0.4 * 0.3));
  CHECK(with.node_mass_kg().sum() - without.node_mass_kg().sum() == Approx(4e-3));
  CHECK_THROWS_WITH(rs::SheetModel(grid, m, {rs::Vec2(0.5, 0.1)}), Catch::Contains("marker 0"));
}
