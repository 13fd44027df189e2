#include "twin/model/material.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "twin/base/atomic_file.h"
#include "twin/base/json_field.h"

namespace twin {
namespace {

using nlohmann::json;

std::string format_value(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& what) {
  throw std::invalid_argument(source + ": field '" + field + "' " + what);
}

void require_positive(double v, const std::string& source, const std::string& field,
                      const char* unit) {
  if (!(std::isfinite(v) && v > 0.0)) {
    fail(source, field, std::string("must be a positive finite number in ") + unit + ", got " +
                            format_value(v));
  }
}

void require_non_negative(double v, const std::string& source, const std::string& field,
                          const char* unit) {
  if (!(std::isfinite(v) && v >= 0.0)) {
    fail(source, field, std::string("must be a finite number >= 0 in ") + unit + ", got " +
                            format_value(v));
  }
}

// A directional property is a number (isotropic) or {"weft": u, "warp": v}.
std::pair<double, double> directional(const JsonField& f, const char* unit) {
  if (f.is_object()) {
    f.only_keys({"weft", "warp"});
    return {f["weft"].number(unit), f["warp"].number(unit)};
  }
  const double v = f.number(unit);
  return {v, v};
}

json directional_json(double u, double v) {
  if (u == v) return u;
  return json{{"weft", u}, {"warp", v}};
}

}  // namespace

Mat3 Material::membrane_stiffness() const {
  const double yu = tensile_stiffness_u_N_m, yv = tensile_stiffness_v_N_m;
  const double nu_uv = poisson_ratio;
  const double nu_vu = nu_uv * yv / yu;
  const double s = 1.0 / (1.0 - nu_uv * nu_vu);
  Mat3 c = Mat3::Zero();
  c(0, 0) = s * yu;
  c(1, 1) = s * yv;
  c(0, 1) = c(1, 0) = s * nu_uv * yv;
  c(2, 2) = shear_stiffness_N_m;
  return c;
}

double Material::bending_coupling_Nm() const {
  return bending_coupling_ratio.value_or(poisson_ratio) *
         std::sqrt(bending_rigidity_u_Nm * bending_rigidity_v_Nm);
}

double Material::twist_rigidity_Nm() const {
  return twist_ratio.value_or(0.5 * (1.0 - poisson_ratio)) *
         std::sqrt(bending_rigidity_u_Nm * bending_rigidity_v_Nm);
}

Mat3 Material::plate_rigidity() const {
  Mat3 d = Mat3::Zero();
  d(0, 0) = bending_rigidity_u_Nm;
  d(1, 1) = bending_rigidity_v_Nm;
  d(0, 1) = d(1, 0) = bending_coupling_Nm();
  d(2, 2) = twist_rigidity_Nm();
  return d;
}

void Material::validate() const {
  const std::string src = "material '" + name + "'";
  require_positive(surface_density_kg_m2, src, "surface_density_kg_m2", "kg/m^2");
  require_positive(tensile_stiffness_u_N_m, src, "tensile_stiffness_N_m.weft", "N/m");
  require_positive(tensile_stiffness_v_N_m, src, "tensile_stiffness_N_m.warp", "N/m");
  require_positive(shear_stiffness_N_m, src, "shear_stiffness_N_m", "N/m");
  require_positive(bending_rigidity_u_Nm, src, "bending_rigidity_Nm.weft", "N*m");
  require_positive(bending_rigidity_v_Nm, src, "bending_rigidity_Nm.warp", "N*m");
  require_non_negative(tensile_viscosity_Ns_m, src, "viscosity.tensile_Ns_m", "N*s/m");
  require_non_negative(shear_viscosity_Ns_m, src, "viscosity.shear_Ns_m", "N*s/m");
  require_non_negative(mass_damping_1_s, src, "viscosity.mass_damping_1_s", "1/s");
  const double coupling =
      poisson_ratio * poisson_ratio * tensile_stiffness_v_N_m / tensile_stiffness_u_N_m;
  if (!(std::isfinite(poisson_ratio) && poisson_ratio >= 0.0 && coupling < 1.0)) {
    fail(src, "poisson_ratio",
         "must be >= 0 with nu^2 * Y_warp / Y_weft < 1 (a stable membrane), got " +
             format_value(poisson_ratio));
  }
  if (thickness_m) require_positive(*thickness_m, src, "thickness_m", "m");
  if ((bending_coupling_ratio || twist_ratio) && bending_model != BendingModel::kPlate) {
    fail(src, bending_coupling_ratio ? "bending_coupling_Nm" : "twist_rigidity_Nm",
         "is a rigidity of the plate bending model only (set \"bending_model\": \"plate\")");
  }
  if (bending_coupling_ratio && !(std::isfinite(*bending_coupling_ratio) &&
                                  std::abs(*bending_coupling_ratio) < 1.0)) {
    fail(src, "bending_coupling_Nm",
         "must satisfy D12^2 < D_weft D_warp (a stable plate), got " + format_value(bending_coupling_Nm()) +
             " N*m");
  }
  if (twist_ratio) require_positive(twist_rigidity_Nm(), src, "twist_rigidity_Nm", "N*m");
  effects.validate(src);
}

double bending_rigidity_from_modulus(double modulus_Pa, double thickness_m, double poisson_ratio) {
  return modulus_Pa * thickness_m * thickness_m * thickness_m /
         (12.0 * (1.0 - poisson_ratio * poisson_ratio));
}

Material material_from_json(const json& j, const std::string& source) {
  const JsonField f(j, source);
  f.only_keys({"name", "surface_density_kg_m2", "tensile_stiffness_N_m", "shear_stiffness_N_m",
               "poisson_ratio", "bending_rigidity_Nm", "bending_modulus_Pa", "thickness_m",
               "viscosity", "bending_given_as", "effects", "bending_model", "bending_coupling_Nm",
               "twist_rigidity_Nm"});
  Material m;
  if (auto name = f.optional("name")) m.name = name->string();
  m.surface_density_kg_m2 = f["surface_density_kg_m2"].number("kg/m^2");
  std::tie(m.tensile_stiffness_u_N_m, m.tensile_stiffness_v_N_m) =
      directional(f["tensile_stiffness_N_m"], "N/m");
  m.shear_stiffness_N_m = f["shear_stiffness_N_m"].number("N/m");
  if (auto nu = f.optional("poisson_ratio")) {
    m.poisson_ratio = nu->number("(dimensionless)");
    if (!(m.poisson_ratio >= 0.0 && m.poisson_ratio < 1.0)) nu->fail("must be in [0, 1)");
  }
  if (auto t = f.optional("thickness_m")) m.thickness_m = t->positive("m");
  const bool rigidity = f.has("bending_rigidity_Nm");
  const bool modulus = f.has("bending_modulus_Pa");
  if (rigidity == modulus) {
    f.fail_child("bending_rigidity_Nm",
                 "or 'bending_modulus_Pa' (with 'thickness_m') must be given, exactly one of them");
  }
  if (auto given = f.optional("bending_given_as")) {
    const std::string expected = rigidity ? "rigidity" : "modulus";
    if (!given->is_string() || given->string() != expected) {
      given->fail("must be \"" + expected + "\" to match the bending field present in the file");
    }
  }
  if (rigidity) {
    std::tie(m.bending_rigidity_u_Nm, m.bending_rigidity_v_Nm) =
        directional(f["bending_rigidity_Nm"], "N*m");
  } else {
    const JsonField field = f["bending_modulus_Pa"];
    auto [eu, ev] = directional(field, "N/m^2");
    if (!(eu > 0.0 && ev > 0.0)) field.fail("must be positive (N/m^2)");
    if (!m.thickness_m) f.fail_child("thickness_m", "is needed to convert bending_modulus_Pa");
    m.bending_modulus_u_Pa = eu;
    m.bending_modulus_v_Pa = ev;
    m.bending_rigidity_u_Nm = bending_rigidity_from_modulus(eu, *m.thickness_m, m.poisson_ratio);
    m.bending_rigidity_v_Nm = bending_rigidity_from_modulus(ev, *m.thickness_m, m.poisson_ratio);
  }
  if (auto model = f.optional("bending_model")) {
    const std::string name = model->string();
    if (name == "plate") {
      m.bending_model = Material::BendingModel::kPlate;
    } else if (name != "hinge") {
      model->fail("must be \"hinge\" or \"plate\", got \"" + name + "\"");
    }
  }
  const double mean_rigidity = std::sqrt(m.bending_rigidity_u_Nm * m.bending_rigidity_v_Nm);
  if (auto d12 = f.optional("bending_coupling_Nm")) m.bending_coupling_ratio = d12->number("N*m") / mean_rigidity;
  if (auto d66 = f.optional("twist_rigidity_Nm")) m.twist_ratio = d66->number("N*m") / mean_rigidity;
  if (auto v = f.optional("viscosity")) {
    v->only_keys({"tensile_Ns_m", "shear_Ns_m", "mass_damping_1_s"});
    if (auto x = v->optional("tensile_Ns_m")) m.tensile_viscosity_Ns_m = x->number("N*s/m");
    if (auto x = v->optional("shear_Ns_m")) m.shear_viscosity_Ns_m = x->number("N*s/m");
    if (auto x = v->optional("mass_damping_1_s")) m.mass_damping_1_s = x->number("1/s");
  }
  if (auto e = f.optional("effects")) m.effects = model_effects_from_json(*e);
  // Range checks, with the file named in every message.
  const std::string name = m.name;
  m.name = source;
  m.validate();
  m.name = name;
  return m;
}

json material_to_json(const Material& m) {
  json j;
  j["name"] = m.name;
  j["surface_density_kg_m2"] = m.surface_density_kg_m2;
  j["tensile_stiffness_N_m"] = directional_json(m.tensile_stiffness_u_N_m, m.tensile_stiffness_v_N_m);
  j["shear_stiffness_N_m"] = m.shear_stiffness_N_m;
  j["poisson_ratio"] = m.poisson_ratio;
  if (m.thickness_m) j["thickness_m"] = *m.thickness_m;
  if (m.bending_given_as_modulus()) {
    j["bending_given_as"] = "modulus";
    j["bending_modulus_Pa"] = directional_json(*m.bending_modulus_u_Pa, *m.bending_modulus_v_Pa);
  } else {
    j["bending_given_as"] = "rigidity";
    j["bending_rigidity_Nm"] = directional_json(m.bending_rigidity_u_Nm, m.bending_rigidity_v_Nm);
  }
  if (m.bending_model == Material::BendingModel::kPlate) j["bending_model"] = "plate";
  if (m.bending_coupling_ratio) j["bending_coupling_Nm"] = m.bending_coupling_Nm();
  if (m.twist_ratio) j["twist_rigidity_Nm"] = m.twist_rigidity_Nm();
  j["viscosity"] = {{"tensile_Ns_m", m.tensile_viscosity_Ns_m},
                    {"shear_Ns_m", m.shear_viscosity_Ns_m},
                    {"mass_damping_1_s", m.mass_damping_1_s}};
  if (m.effects.any()) j["effects"] = model_effects_to_json(m.effects);
  return j;
}

Material read_material_file(const std::string& path) {
  return material_from_json(JsonField::parse_file(path), path);
}

void write_material_file(const std::string& path, const Material& m) {
  write_file_atomically(path, [&](std::ostream& out) { out << material_to_json(m).dump(2) << "\n"; });
}

}  // namespace twin
