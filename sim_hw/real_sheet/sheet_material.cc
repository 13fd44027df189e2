#include "sim_hw/real_sheet/sheet_material.h"

#include <cmath>
#include <numbers>

namespace sim_hw::real_sheet {

Eigen::Matrix3d SheetMaterial::bending_D_Nm() const {
  Eigen::Matrix3d D;
  D << D11_Nm, D12_Nm, 0, D12_Nm, D22_Nm, 0, 0, 0, D66_Nm;
  return D;
}

double SheetMaterial::creep_factor(double age_s) const {
  if (creep_fraction == 0) return 1.0;
  const double phi = creep_fraction / (1.0 - creep_fraction);
  const double crept = std::isnan(age_s) ? 1.0 : 1.0 - std::exp(-std::max(0.0, age_s) / creep_time_s);
  return 1.0 / (1.0 + phi * crept);
}

SheetMaterial sheet_material_from(const twin::Material& m) {
  SheetMaterial s;
  s.density_kg_m2 = m.surface_density_kg_m2;
  const double nu_uv = m.poisson_ratio;
  const double nu_vu = nu_uv * m.tensile_stiffness_v_N_m / m.tensile_stiffness_u_N_m;
  const double q = 1.0 - nu_uv * nu_vu;
  s.membrane_C_N_m << m.tensile_stiffness_u_N_m / q, nu_uv * m.tensile_stiffness_v_N_m / q, 0,
      nu_uv * m.tensile_stiffness_v_N_m / q, m.tensile_stiffness_v_N_m / q, 0, 0, 0, m.shear_stiffness_N_m;
  s.D11_Nm = m.bending_rigidity_u_Nm;
  s.D22_Nm = m.bending_rigidity_v_Nm;
  const double mean = std::sqrt(s.D11_Nm * s.D22_Nm);
  s.D12_Nm = nu_uv * mean;
  s.D66_Nm = 0.5 * (1.0 - nu_uv) * mean;
  s.tensile_viscosity_Ns_m = m.tensile_viscosity_Ns_m;
  s.shear_viscosity_Ns_m = m.shear_viscosity_Ns_m;
  s.mass_damping_1_s = m.mass_damping_1_s;
  const twin::ModelEffects& e = m.effects;
  s.rest_curvature_1_m << e.rest_curvature_uu_1_m, e.rest_curvature_uv_1_m, e.rest_curvature_uv_1_m,
      e.rest_curvature_vv_1_m;
  s.stiffening_m2 = e.bending_stiffening_m2;
  s.marker_mass_kg = e.marker_mass_kg;
  s.creep_fraction = e.relaxation_fraction;
  s.creep_time_s = e.relaxation_time_s;
  s.pad_strength = e.clamp_grip_strength;
  s.pad_extension_m = e.clamp_grip_strength > 0 ? e.clamp_grip_width_m : 0.0;
  s.slip_compliance_m_N = e.clamp_slip_compliance_m_N;
  return s;
}

Eigen::Vector3d rest_curvature_at(const SheetMaterial& material, const Vec2& uv_m) {
  Eigen::Matrix2d K = material.rest_curvature_1_m;
  for (const CreaseBand& c : material.creases) {
    // Distance from the line, and the band's curvature there: angle spread over the width with
    // a raised cosine, whose integral across the band is the fold angle.
    const Vec2 t(std::cos(c.direction_rad), std::sin(c.direction_rad)), n(-t.y(), t.x());
    const double d = (uv_m - c.point_m).dot(n);
    if (std::abs(d) >= 0.5 * c.width_m) continue;
    const double profile = (1.0 + std::cos(2.0 * std::numbers::pi * d / c.width_m)) / c.width_m;
    K += c.angle_rad * profile * n * n.transpose();
  }
  return Eigen::Vector3d(K(0, 0), K(1, 1), 2.0 * K(0, 1));
}

}  // namespace sim_hw::real_sheet
