#include "twin/model/model_effects.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "twin/base/json_field.h"

namespace twin {
namespace {

const ModelEffects kDefaults{};

[[noreturn]] void fail(const std::string& source, const char* field, double value,
                       const std::string& expected) {
  std::ostringstream s;
  s.precision(6);
  s << source << ": field 'effects." << field << "' must be " << expected << ", got " << value;
  throw std::invalid_argument(s.str());
}

}  // namespace

bool ModelEffects::has_rest_curvature() const {
  return rest_curvature_uu_1_m != 0.0 || rest_curvature_vv_1_m != 0.0 ||
         rest_curvature_uv_1_m != 0.0;
}

bool ModelEffects::any() const {
  return has_rest_curvature() || bending_stiffening_m2 != 0.0 || marker_mass_kg != 0.0 ||
         relaxation_fraction != 0.0 || relaxation_time_s != kDefaults.relaxation_time_s ||
         clamp_grip_strength != 0.0 || clamp_grip_width_m != kDefaults.clamp_grip_width_m ||
         clamp_slip_compliance_m_N != 0.0;
}

double ModelEffects::relaxation_factor(double age_s) const {
  if (relaxation_fraction == 0.0) return 1.0;
  if (!std::isfinite(age_s)) return 1.0 - relaxation_fraction;
  return 1.0 - relaxation_fraction * (1.0 - std::exp(-std::max(age_s, 0.0) / relaxation_time_s));
}

void ModelEffects::validate(const std::string& source) const {
  const double curvatures[3] = {rest_curvature_uu_1_m, rest_curvature_vv_1_m, rest_curvature_uv_1_m};
  const char* names[3] = {"rest_curvature_uu_1_m", "rest_curvature_vv_1_m", "rest_curvature_uv_1_m"};
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(curvatures[i])) fail(source, names[i], curvatures[i], "a finite number (1/m)");
  }
  if (!(std::isfinite(bending_stiffening_m2) && bending_stiffening_m2 >= 0.0)) {
    fail(source, "bending_stiffening_m2", bending_stiffening_m2, "a finite number >= 0 (m^2)");
  }
  if (!(std::isfinite(marker_mass_kg) && marker_mass_kg >= 0.0)) {
    fail(source, "marker_mass_kg", marker_mass_kg, "a finite number >= 0 (kg)");
  }
  if (!(relaxation_fraction >= 0.0 && relaxation_fraction < 1.0)) {
    fail(source, "relaxation_fraction", relaxation_fraction, "in [0, 1)");
  }
  if (!(std::isfinite(relaxation_time_s) && relaxation_time_s > 0.0)) {
    fail(source, "relaxation_time_s", relaxation_time_s, "a positive finite number (s)");
  }
  if (!(std::isfinite(clamp_grip_strength) && clamp_grip_strength >= 0.0)) {
    fail(source, "clamp_grip.strength", clamp_grip_strength, "a finite number >= 0");
  }
  if (!(clamp_grip_width_m > 0.0 && clamp_grip_width_m <= kMaxClampGripWidth_m)) {
    fail(source, "clamp_grip.width_m", clamp_grip_width_m, "in (0, 0.15] (m)");
  }
  if (!(clamp_slip_compliance_m_N >= 0.0 && clamp_slip_compliance_m_N <= kMaxClampSlipCompliance_m_N)) {
    fail(source, "clamp_slip.compliance_m_N", clamp_slip_compliance_m_N, "in [0, 0.1] (m/N)");
  }
}

ModelEffects model_effects_from_json(const JsonField& block) {
  block.only_keys({"rest_curvature_1_m", "bending_stiffening_m2", "marker_mass_kg", "relaxation", "clamp_grip",
                   "clamp_slip"});
  ModelEffects e;
  if (auto k = block.optional("rest_curvature_1_m")) {
    k->only_keys({"uu", "vv", "uv"});
    if (auto x = k->optional("uu")) e.rest_curvature_uu_1_m = x->number("1/m");
    if (auto x = k->optional("vv")) e.rest_curvature_vv_1_m = x->number("1/m");
    if (auto x = k->optional("uv")) e.rest_curvature_uv_1_m = x->number("1/m");
  }
  if (auto x = block.optional("bending_stiffening_m2")) e.bending_stiffening_m2 = x->non_negative("m^2");
  if (auto x = block.optional("marker_mass_kg")) e.marker_mass_kg = x->non_negative("kg");
  if (auto c = block.optional("clamp_grip")) {
    c->only_keys({"strength", "width_m"});
    if (auto x = c->optional("strength")) e.clamp_grip_strength = x->non_negative("(dimensionless)");
    if (auto x = c->optional("width_m")) e.clamp_grip_width_m = x->positive("m");
  }
  if (auto c = block.optional("clamp_slip")) {
    c->only_keys({"compliance_m_N"});
    if (auto x = c->optional("compliance_m_N")) e.clamp_slip_compliance_m_N = x->non_negative("m/N");
  }
  if (auto r = block.optional("relaxation")) {
    r->only_keys({"fraction", "time_s"});
    if (auto x = r->optional("fraction")) {
      e.relaxation_fraction = x->non_negative("(dimensionless)");
      if (!(e.relaxation_fraction < 1.0)) x->fail("must be in [0, 1)");
    }
    if (auto x = r->optional("time_s")) e.relaxation_time_s = x->positive("s");
  }
  e.validate(block.source());
  return e;
}

nlohmann::json model_effects_to_json(const ModelEffects& e) {
  nlohmann::json j = nlohmann::json::object();
  if (e.has_rest_curvature()) {
    j["rest_curvature_1_m"] = {{"uu", e.rest_curvature_uu_1_m},
                               {"vv", e.rest_curvature_vv_1_m},
                               {"uv", e.rest_curvature_uv_1_m}};
  }
  if (e.bending_stiffening_m2 != kDefaults.bending_stiffening_m2) {
    j["bending_stiffening_m2"] = e.bending_stiffening_m2;
  }
  if (e.marker_mass_kg != kDefaults.marker_mass_kg) j["marker_mass_kg"] = e.marker_mass_kg;
  if (e.clamp_grip_strength != kDefaults.clamp_grip_strength || e.clamp_grip_width_m != kDefaults.clamp_grip_width_m) {
    j["clamp_grip"] = {{"strength", e.clamp_grip_strength}, {"width_m", e.clamp_grip_width_m}};
  }
  if (e.clamp_slip_compliance_m_N != kDefaults.clamp_slip_compliance_m_N) {
    j["clamp_slip"] = {{"compliance_m_N", e.clamp_slip_compliance_m_N}};
  }
  if (e.relaxation_fraction != kDefaults.relaxation_fraction ||
      e.relaxation_time_s != kDefaults.relaxation_time_s) {
    j["relaxation"] = {{"fraction", e.relaxation_fraction}, {"time_s", e.relaxation_time_s}};
  }
  return j;
}

}  // namespace twin
