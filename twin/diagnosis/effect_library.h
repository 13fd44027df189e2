#pragma once
// The library of candidate effects the discrepancy workflow (issue 6) can name: each an optional
// term of the twin (twin/model/model_effects.h, or the per-direction stiffnesses of the material) with
// its own parameters. For every candidate: the parameters it adds to the base fit, how it changes
// the base parameter list, which added parameters the score test uses, and what the data must
// contain for the effect to be identifiable at all.
//
// Null values: every added parameter's absence is its model_effects.h default (0 for the
// effects' amplitudes), except orthotropic stiffness, whose "added" parameters (the warp values)
// are absent when they equal the weft ones. null_material() sets a material to the null of a
// candidate, so a refit starts at the base fit with the effect absent.

#include <optional>
#include <string>
#include <vector>

#include "twin/model/material_parameters.h"
#include "twin/trials/trial.h"

namespace twin::diagnosis {

struct CandidateEffect {
  std::string name;         // fixed string used in files and verdicts (common contract)
  std::string description;  // one line of physics
  // The parameters a refit varies: the base list as this candidate changes it (orthotropic
  // stiffness splits the paired kTensile / kBending into per-direction ones), then the added
  // ones; base_count entries come first.
  std::vector<MaterialParameter> refit_parameters;
  int base_count = 0;
  // The parameters of the score test: the base fit's own (base_parameters(), first) and then
  // the added ones, so the first columns of its Jacobian span exactly the base model. For
  // orthotropic stiffness these are {kTensile, kShear, kBending, kTensileV, kBendingV}: the
  // columns of the paired ones move both directions, the V ones the warp alone, which spans
  // the per-direction model (the CAUTION of common.md concerns material_at, and the test only
  // evaluates at the isotropic base fit, where u = v). For relaxation the test uses the
  // fraction with tau at its default: tau has no sensitivity while the fraction is zero; for
  // clamp grip likewise the strength, with the width profiled (score_profile below).
  std::vector<MaterialParameter> score_parameters;
  enum class Needs { kNothing, kMarkerStages, kStageAges };
  Needs needs = Needs::kNothing;
  // A parameter the score test cannot linearise in (it has no sensitivity while the effect is
  // absent, so the effect's columns depend on its value) and the values it is tried at: the
  // test is made at each, the largest statistic kept and its p-value multiplied by the number of
  // values (Bonferroni). Clamp grip: the width, over its range, since a grip the jaws' own width
  // and one of 12 cm move the markers in different patterns, and the default 5 cm alone left a
  // 26 mm grip ranked below three other candidates (blind set 7003). Relaxation's time is left at
  // its default: that test's sensitivity barely changes shape with tau (a scale of the fraction).
  struct Profile {
    MaterialParameter parameter;
    std::vector<double> values;
  };
  std::optional<Profile> score_profile;

  int added_count() const { return static_cast<int>(refit_parameters.size()) - base_count; }
  int score_dof() const { return static_cast<int>(score_parameters.size()) - 3; }
};

// The base fit's parameters (the paper's isotropic three).
const std::vector<MaterialParameter>& base_parameters();

// The candidates, in a fixed order: orthotropic_stiffness, rest_curvature, nonlinear_bending,
// marker_mass, viscoelastic_relaxation, clamp_grip, clamp_slip.
const std::vector<CandidateEffect>& effect_library();

// The candidate named `name`; throws std::invalid_argument quoting it and listing the names.
const CandidateEffect& find_effect(const std::string& name);

// The named candidates of a comma-separated list ("" or "all": every one). Throws as find_effect.
std::vector<CandidateEffect> select_effects(const std::string& list);

// Empty when the training trials can identify the effect; otherwise why not (the candidate is
// then skipped and the reason reported). Marker mass needs marker stages (a point mass where
// each marker is glued: clouds do not say where that is). Relaxation needs time-stamped marker
// stages scanned at different ages (seconds since the clamps last moved); with equal ages it is
// indistinguishable from a stiffness change. Ages as residual_field.h's stage_age_s().
std::string applicability(const CandidateEffect& effect, const std::vector<const Trial*>& training);

// `material` with the candidate absent: effects at their defaults and, for orthotropic
// stiffness, the warp (v) stiffnesses set to the weft (u) ones.
Material null_material(const CandidateEffect& effect, Material material);

}  // namespace twin::diagnosis
