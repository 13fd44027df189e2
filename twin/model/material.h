#pragma once
// Material of a sheet: what the twin needs to know about a prepreg or fabric ply.
//
// Membrane law (Volino et al. 2009), on the Green-Lagrange strain (eps_uu, eps_vv, gamma_uv)
// with gamma_uv = U.V the engineering shear, in the material frame u = weft, v = warp:
//   sigma = C eps + C' d(eps)/dt            (N/m, second Piola-Kirchhoff, per unit rest length)
//   C  = [[Y_u, nu_uv Y_v, 0], [nu_uv Y_v, Y_v, 0], [0, 0, G (1 - nu_uv nu_vu)]] / (1 - nu_uv nu_vu)
//        (orthotropic plane stress, nu_vu = nu_uv Y_v / Y_u so C is symmetric; C33 = G);
//        Y = tensile stiffness (Young's modulus times thickness) and G = shear stiffness, N/m.
//   C' = diag(eta_t, eta_t, eta_s)          (N*s/m), the strain-rate viscosity.
// Bending: plate rigidity D (N*m) for curvature along u and along v; an isotropic sheet has
// D_u = D_v. When a bending modulus E_b (N/m^2, as the paper quotes for the composite) is given
// instead, D = E_b t^3 / (12 (1 - nu^2)) with thickness t (m) and the given Poisson ratio nu
// (nu_uv; for an orthotropic membrane the bending conversion still uses this one value).
//
// Bending model: "hinge" (paper, Eq. 10: one stiffness per interior edge, calibrated so that
// cylinders along u and v match D_u and D_v; in double curvature it behaves as a plate of
// Poisson ratio about -1/3, bending_calibration.h) or "plate" (plate_bending.h: a curvature
// tensor per triangle with the full rigidity matrix on (K_uu, K_vv, 2 K_uv))
//   D = [[D_u, D12, 0], [D12, D_v, 0], [0, 0, D66]]                     (N*m)
// where D12 and D66 default to Huber's orthotropic plate, D12 = nu sqrt(D_u D_v) and
// D66 = (1 - nu)/2 sqrt(D_u D_v), the isotropic plate when D_u = D_v, and a laminate's own
// values may be given. They are kept as ratios to sqrt(D_u D_v), so scaling the bending (as
// identification does) scales them with it.

#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "twin/model/model_effects.h"
#include "twin/base/types.h"

namespace twin {

struct Material {
  std::string name = "unnamed";
  double surface_density_kg_m2 = 0.3;
  double tensile_stiffness_u_N_m = 5000.0;   // weft
  double tensile_stiffness_v_N_m = 5000.0;   // warp
  double shear_stiffness_N_m = 5000.0;
  double poisson_ratio = 0.3;                // nu_uv, in-plane, 0 <= nu < 1 with the bound below
  double bending_rigidity_u_Nm = 1e-3;       // D for curvature along u (bends the weft yarns)
  double bending_rigidity_v_Nm = 1e-3;       // D for curvature along v (bends the warp yarns)
  enum class BendingModel { kHinge, kPlate };
  BendingModel bending_model = BendingModel::kHinge;
  // D12 / sqrt(D_u D_v) and D66 / sqrt(D_u D_v); unset: Huber's plate from poisson_ratio. Only
  // the plate model has them.
  std::optional<double> bending_coupling_ratio;
  std::optional<double> twist_ratio;
  double tensile_viscosity_Ns_m = 0.0;       // eta_t, strain-rate viscosity of eps_uu, eps_vv
  double shear_viscosity_Ns_m = 0.0;         // eta_s, strain-rate viscosity of gamma_uv
  double mass_damping_1_s = 0.0;             // alpha, force -alpha m v (air drag, 1/s)

  // Provenance of the bending figure, kept so a written file says what was given.
  std::optional<double> thickness_m;
  std::optional<double> bending_modulus_u_Pa;  // set when bending was given as a modulus
  std::optional<double> bending_modulus_v_Pa;

  // Effects beyond the paper's model (model_effects.h); all absent by default.
  ModelEffects effects;

  bool bending_given_as_modulus() const { return bending_modulus_u_Pa.has_value(); }
  // 3x3 membrane stiffness C (N/m) on (eps_uu, eps_vv, gamma_uv).
  Mat3 membrane_stiffness() const;
  // D12 and D66 (N*m), given or Huber's.
  double bending_coupling_Nm() const;
  double twist_rigidity_Nm() const;
  // 3x3 plate rigidity D (N*m) on (K_uu, K_vv, 2 K_uv), see above.
  Mat3 plate_rigidity() const;
  // Throws std::invalid_argument naming the field when a value is out of range.
  void validate() const;
};

// D = E t^3 / (12 (1 - nu^2)), N*m from N/m^2, m.
double bending_rigidity_from_modulus(double modulus_Pa, double thickness_m, double poisson_ratio);

// Material file (JSON), see docs/file_formats.md ("Material file"). `source` names the file in error messages.
Material material_from_json(const nlohmann::json& j, const std::string& source);
nlohmann::json material_to_json(const Material& m);
Material read_material_file(const std::string& path);
// Writes atomically (temporary file, then rename): an existing file is never left half-written.
void write_material_file(const std::string& path, const Material& m);

}  // namespace twin
