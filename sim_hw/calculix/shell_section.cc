#include "sim_hw/calculix/shell_section.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::calculix {

ShellSection shell_section(const twin::Material& m, ShearFrom shear) {
  const twin::ModelEffects& e = m.effects;
  const twin::ModelEffects none;
  const auto refuse = [&](const char* what) {
    throw std::invalid_argument(fmt::format("CalculiX section: material '{}' has {} (effects.{}), which the CalculiX "
                                            "opinion has no form of; compare the paper's model only",
                                            m.name, what, what));
  };
  if (e.has_rest_curvature()) refuse("rest_curvature");
  if (e.bending_stiffening_m2 != none.bending_stiffening_m2) refuse("bending_stiffening_m2");
  if (e.relaxation_fraction != none.relaxation_fraction) refuse("relaxation_fraction");
  if (e.marker_mass_kg != none.marker_mass_kg) refuse("marker_mass_kg");
  if (e.clamp_grip_strength != none.clamp_grip_strength) refuse("clamp_grip_strength");
  if (e.clamp_slip_compliance_m_N != none.clamp_slip_compliance_m_N) refuse("clamp_slip_compliance_m_N");
  const twin::Mat3 d = m.plate_rigidity();        // N*m on (K_uu, K_vv, 2 K_uv)
  const twin::Mat3 c = m.membrane_stiffness();    // N/m on (eps_uu, eps_vv, gamma_uv)
  ShellSection s;
  s.thickness_m = std::sqrt(12.0 * d(0, 0) / c(0, 0));
  s.density_kg_m3 = m.surface_density_kg_m2 / s.thickness_m;
  twin::Mat3 q = 12.0 * d / std::pow(s.thickness_m, 3);  // Pa
  if (shear == ShearFrom::kMembrane) q(2, 2) = c(2, 2) / s.thickness_m;
  s.e1_Pa = q(0, 0) - q(0, 1) * q(0, 1) / q(1, 1);
  s.e2_Pa = q(1, 1) - q(0, 1) * q(0, 1) / q(0, 0);
  s.nu12 = q(0, 1) / q(1, 1);
  s.g12_Pa = q(2, 2);
  const twin::Mat3 shell_membrane = q * s.thickness_m;
  s.membrane_v_ratio = shell_membrane(1, 1) / c(1, 1);
  s.membrane_coupling_ratio = c(0, 1) != 0 ? shell_membrane(0, 1) / c(0, 1) : 1.0;
  s.membrane_shear_ratio = shell_membrane(2, 2) / c(2, 2);
  s.twist_ratio = q(2, 2) * std::pow(s.thickness_m, 3) / 12.0 / d(2, 2);
  s.isotropic = std::abs(s.e1_Pa - s.e2_Pa) <= 1e-9 * s.e1_Pa &&
                std::abs(s.g12_Pa - s.e1_Pa / (2 * (1 + s.nu12))) <= 1e-9 * s.e1_Pa;
  return s;
}

std::string ShellSection::text() const {
  return fmt::format("shell section: t {:.3f} mm, {:.1f} kg/m^3, E1 {:.4g} E2 {:.4g} G12 {:.4g} MPa, nu12 {:.3f} ({}); "
                     "bending D11 D22 D12 exact, D66 x{:.3f}; membrane C11 exact, C22 x{:.3f}, C12 x{:.3f}, C66 x{:.3f}",
                     1e3 * thickness_m, density_kg_m3, 1e-6 * e1_Pa, 1e-6 * e2_Pa, 1e-6 * g12_Pa, nu12,
                     isotropic ? "isotropic" : "orthotropic", twist_ratio, membrane_v_ratio, membrane_coupling_ratio,
                     membrane_shear_ratio);
}

}  // namespace sim_hw::calculix
