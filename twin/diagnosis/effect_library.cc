#include "twin/diagnosis/effect_library.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "twin/diagnosis/residual_field.h"
#include "twin/model/model_effects.h"

namespace twin::diagnosis {

using P = MaterialParameter;

const std::vector<MaterialParameter>& base_parameters() {
  static const std::vector<MaterialParameter> base = {P::kTensile, P::kShear, P::kBending};
  return base;
}

const std::vector<CandidateEffect>& effect_library() {
  static const std::vector<CandidateEffect> library = [] {
    std::vector<CandidateEffect> l;
    l.push_back({"orthotropic_stiffness",
                 "warp and weft differ: separate tensile stiffness and bending rigidity along u and v",
                 {P::kTensileU, P::kShear, P::kBendingU, P::kTensileV, P::kBendingV},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kTensileV, P::kBendingV},
                 CandidateEffect::Needs::kNothing, std::nullopt});
    l.push_back({"rest_curvature", "roll set: the ply is curved at rest (curvature tensor K0 in the material frame)",
                 {P::kTensile, P::kShear, P::kBending, P::kRestCurvatureUU, P::kRestCurvatureVV, P::kRestCurvatureUV},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kRestCurvatureUU, P::kRestCurvatureVV, P::kRestCurvatureUV},
                 CandidateEffect::Needs::kNothing, std::nullopt});
    l.push_back({"nonlinear_bending", "strain-dependent bending: M = D k (1 + beta k^2)",
                 {P::kTensile, P::kShear, P::kBending, P::kBendingStiffening},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kBendingStiffening},
                 CandidateEffect::Needs::kNothing, std::nullopt});
    l.push_back({"marker_mass", "each scan marker adds a point mass where it is glued",
                 {P::kTensile, P::kShear, P::kBending, P::kMarkerMass},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kMarkerMass},
                 CandidateEffect::Needs::kMarkerStages, std::nullopt});
    l.push_back({"viscoelastic_relaxation",
                 "stiffnesses relax by a fraction with time constant tau after the clamps move",
                 {P::kTensile, P::kShear, P::kBending, P::kRelaxationFraction, P::kRelaxationTime},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kRelaxationFraction},
                 CandidateEffect::Needs::kStageAges, std::nullopt});
    l.push_back({"clamp_grip", "the clamps' jaws grip a wider patch than the trial's grip radii say",
                 {P::kTensile, P::kShear, P::kBending, P::kClampGripStrength, P::kClampGripWidth},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kClampGripStrength},
                 CandidateEffect::Needs::kNothing,
                 // Doubling widths over the parameter's range (kMaxClampGripWidth_m = 15 cm).
                 CandidateEffect::Profile{P::kClampGripWidth, {0.015, 0.03, 0.06, 0.12}}});
    l.push_back({"clamp_slip", "the ply slides in the clamps' jaws: each patch gives way along the jaw faces under its pull",
                 {P::kTensile, P::kShear, P::kBending, P::kClampSlipCompliance},
                 3,
                 {P::kTensile, P::kShear, P::kBending, P::kClampSlipCompliance},
                 CandidateEffect::Needs::kNothing, std::nullopt});
    return l;
  }();
  return library;
}

const CandidateEffect& find_effect(const std::string& name) {
  std::string names;
  for (const CandidateEffect& e : effect_library()) {
    if (e.name == name) return e;
    names += (names.empty() ? "" : ", ") + e.name;
  }
  throw std::invalid_argument("unknown effect \"" + name + "\" (expected one of: " + names + ")");
}

std::vector<CandidateEffect> select_effects(const std::string& list) {
  if (list.empty() || list == "all") return effect_library();
  std::vector<CandidateEffect> chosen;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    if (!name.empty()) chosen.push_back(find_effect(name));
  }
  if (chosen.empty()) throw std::invalid_argument("--effects: expected a comma-separated list of effect names");
  return chosen;
}

std::string applicability(const CandidateEffect& effect, const std::vector<const Trial*>& training) {
  int marker_stages = 0;
  double youngest = INFINITY, oldest = -INFINITY;
  for (const Trial* t : training) {
    for (std::size_t s = 0; s < t->stages.size(); ++s) {
      if (!t->stages[s].observed.has_markers()) continue;
      ++marker_stages;
      const double age = stage_age_s(*t, static_cast<int>(s));
      if (std::isfinite(age)) {
        youngest = std::min(youngest, age);
        oldest = std::max(oldest, age);
      }
    }
  }
  switch (effect.needs) {
    case CandidateEffect::Needs::kNothing:
      return "";
    case CandidateEffect::Needs::kMarkerStages:
      return marker_stages > 0 ? "" : "needs marker stages (the training trials have only point clouds)";
    case CandidateEffect::Needs::kStageAges:
      // Ages that differ by less than a factor 1.5 leave relaxation nearly a plain stiffness
      // change (the factor 1 - f (1 - exp(-a/tau)) barely differs between them).
      if (!std::isfinite(youngest)) return "needs time-stamped marker stages (no stage age is known)";
      if (oldest < 1.5 * youngest) return "needs marker stages scanned at different ages (all within a factor 1.5)";
      return "";
  }
  return "";
}

Material null_material(const CandidateEffect& effect, Material material) {
  if (effect.name == "orthotropic_stiffness") {
    material.tensile_stiffness_v_N_m = material.tensile_stiffness_u_N_m;
    material.bending_rigidity_v_Nm = material.bending_rigidity_u_Nm;
    return material;
  }
  // Only this candidate's parameters go back to their defaults: effects the base material
  // already has (a user's augmented file) stay.
  Material defaults;
  defaults.effects = ModelEffects{};
  for (std::size_t j = effect.base_count; j < effect.refit_parameters.size(); ++j) {
    set_parameter(material, effect.refit_parameters[j], get_parameter(defaults, effect.refit_parameters[j]));
  }
  return material;
}

}  // namespace twin::diagnosis
