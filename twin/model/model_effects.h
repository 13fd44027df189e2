#pragma once
// Optional physical effects of the twin beyond the paper's model: the terms the discrepancy
// workflow (issue 6) can name, fit and add. They live in the material file's "effects" block
// (docs/file_formats.md, "Material file"), so the twin, identification and the cell use them with no code
// change. Every field's default is the paper's model (the effect absent), and a file without the
// block reads as that.
//
//   rest curvature (roll set)   the ply was stored rolled: at rest it is not flat but curved,
//                               with the curvature tensor K0 (1/m) in the material frame
//                               (uu: curvature along u, bending the weft yarns; vv along v;
//                               uv the twist). Hinge rest angles follow from K0.
//   bending stiffening          strain-dependent bending: the bending moment is
//                               M = D kappa (1 + beta kappa^2), beta (m^2) >= 0.
//   marker mass                 each scan marker adds a point mass (kg) where it is glued. Only
//                               trials know where markers are; the cell's ply has none.
//   viscoelastic relaxation     after the clamps move, the stiffnesses relax towards
//                               (1 - fraction) of their value with time constant tau (s):
//                               factor(a) = 1 - fraction (1 - exp(-a / tau)) at a seconds since
//                               the clamps last moved (a quasi-elastic approximation of a
//                               standard linear solid: the equilibrium under the relaxed
//                               modulus). Needs time-stamped stages.
//   clamp grip                  the jaws hold a wider patch than the clamps' grip radii say:
//                               material up to a width w (m) beyond a clamp's radius is held
//                               too, with a strength s (1: as firmly as the clamp's own patch,
//                               0: not at all; clamp_grip_term.h). Only models that know the
//                               clamps (ShellModel::set_clamp_grips) apply it.
//   clamp slip                  the ply slides in the jaws: each clamp's patch gives way along
//                               the jaw faces by c (m/N) per newton of the pull it holds
//                               (clamp_slip_term.h; 0: the jaws hold it rigidly). Only models
//                               that know the clamps (ShellModel::set_clamp_slips) apply it.
// Orthotropic stiffness (warp != weft) is not here: the material has had per-direction tensile
// stiffness and bending rigidity from the start.

#include <string>

#include <nlohmann/json_fwd.hpp>

namespace twin {

class JsonField;

// The widest grip the twin represents (m): springs are built out to this beyond each radius.
inline constexpr double kMaxClampGripWidth_m = 0.15;
// The loosest jaws the twin represents (m/N): 10 cm of slip per newton of pull.
inline constexpr double kMaxClampSlipCompliance_m_N = 0.1;

struct ModelEffects {
  double rest_curvature_uu_1_m = 0.0;  // 1/m
  double rest_curvature_vv_1_m = 0.0;  // 1/m
  double rest_curvature_uv_1_m = 0.0;  // 1/m (twist)
  double bending_stiffening_m2 = 0.0;  // beta, m^2, >= 0
  double marker_mass_kg = 0.0;         // per marker, kg, >= 0
  double relaxation_fraction = 0.0;    // in [0, 1)
  double relaxation_time_s = 60.0;     // tau, s, > 0 (irrelevant while the fraction is 0)
  double clamp_grip_strength = 0.0;    // s, >= 0 (0: the effect absent)
  double clamp_grip_width_m = 0.05;    // w, m, in (0, kMaxClampGripWidth_m] (irrelevant while s is 0)
  double clamp_slip_compliance_m_N = 0.0;  // c, m/N, in [0, kMaxClampSlipCompliance_m_N] (0: absent)

  bool has_rest_curvature() const;
  // True when any effect is present (a field away from its default).
  bool any() const;
  // Stiffness factor after `age_s` seconds since the clamps last moved (1 without relaxation;
  // an unknown age, NaN, counts as fully relaxed).
  double relaxation_factor(double age_s) const;
  // Throws std::invalid_argument naming `source` and the field ("effects.<name>").
  void validate(const std::string& source) const;
};

// The "effects" block of a material file. Unknown keys are errors (naming them); absent keys
// keep their defaults.
ModelEffects model_effects_from_json(const JsonField& block);
// Only the fields away from their defaults (an empty object when none is).
nlohmann::json model_effects_to_json(const ModelEffects& effects);

}  // namespace twin
