#include "twin/model/material_parameters.h"

#include <cmath>
#include <stdexcept>

namespace twin {

double get_parameter(const Material& m, MaterialParameter parameter) {
  switch (parameter) {
    case MaterialParameter::kTensile:
    case MaterialParameter::kTensileU: return m.tensile_stiffness_u_N_m;
    case MaterialParameter::kTensileV: return m.tensile_stiffness_v_N_m;
    case MaterialParameter::kShear: return m.shear_stiffness_N_m;
    case MaterialParameter::kBending:
    case MaterialParameter::kBendingU: return m.bending_rigidity_u_Nm;
    case MaterialParameter::kBendingV: return m.bending_rigidity_v_Nm;
    case MaterialParameter::kSurfaceDensity: return m.surface_density_kg_m2;
    case MaterialParameter::kBendingCoupling: return m.bending_coupling_ratio.value_or(m.poisson_ratio);
    case MaterialParameter::kTwist: return m.twist_ratio.value_or(0.5 * (1.0 - m.poisson_ratio));
    case MaterialParameter::kRestCurvatureUU: return m.effects.rest_curvature_uu_1_m;
    case MaterialParameter::kRestCurvatureVV: return m.effects.rest_curvature_vv_1_m;
    case MaterialParameter::kRestCurvatureUV: return m.effects.rest_curvature_uv_1_m;
    case MaterialParameter::kBendingStiffening: return m.effects.bending_stiffening_m2;
    case MaterialParameter::kMarkerMass: return m.effects.marker_mass_kg;
    case MaterialParameter::kRelaxationFraction: return m.effects.relaxation_fraction;
    case MaterialParameter::kRelaxationTime: return m.effects.relaxation_time_s;
    case MaterialParameter::kClampGripStrength: return m.effects.clamp_grip_strength;
    case MaterialParameter::kClampGripWidth: return m.effects.clamp_grip_width_m;
    case MaterialParameter::kClampSlipCompliance: return m.effects.clamp_slip_compliance_m_N;
  }
  throw std::invalid_argument("get_parameter: unknown MaterialParameter " +
                              std::to_string(static_cast<int>(parameter)));
}

void set_parameter(Material& m, MaterialParameter parameter, double value) {
  switch (parameter) {
    case MaterialParameter::kTensile:
      m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = value;
      return;
    case MaterialParameter::kTensileU: m.tensile_stiffness_u_N_m = value; return;
    case MaterialParameter::kTensileV: m.tensile_stiffness_v_N_m = value; return;
    case MaterialParameter::kShear: m.shear_stiffness_N_m = value; return;
    case MaterialParameter::kBending:
      m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = value;
      return;
    case MaterialParameter::kBendingU: m.bending_rigidity_u_Nm = value; return;
    case MaterialParameter::kBendingV: m.bending_rigidity_v_Nm = value; return;
    case MaterialParameter::kSurfaceDensity: m.surface_density_kg_m2 = value; return;
    case MaterialParameter::kBendingCoupling: m.bending_coupling_ratio = value; return;
    case MaterialParameter::kTwist: m.twist_ratio = value; return;
    case MaterialParameter::kRestCurvatureUU: m.effects.rest_curvature_uu_1_m = value; return;
    case MaterialParameter::kRestCurvatureVV: m.effects.rest_curvature_vv_1_m = value; return;
    case MaterialParameter::kRestCurvatureUV: m.effects.rest_curvature_uv_1_m = value; return;
    case MaterialParameter::kBendingStiffening: m.effects.bending_stiffening_m2 = value; return;
    case MaterialParameter::kMarkerMass: m.effects.marker_mass_kg = value; return;
    case MaterialParameter::kRelaxationFraction: m.effects.relaxation_fraction = value; return;
    case MaterialParameter::kRelaxationTime: m.effects.relaxation_time_s = value; return;
    case MaterialParameter::kClampGripStrength: m.effects.clamp_grip_strength = value; return;
    case MaterialParameter::kClampGripWidth: m.effects.clamp_grip_width_m = value; return;
    case MaterialParameter::kClampSlipCompliance: m.effects.clamp_slip_compliance_m_N = value; return;
  }
  throw std::invalid_argument("set_parameter: unknown MaterialParameter " +
                              std::to_string(static_cast<int>(parameter)));
}

void scale_parameter(Material& m, MaterialParameter parameter, double factor) {
  switch (parameter) {
    case MaterialParameter::kTensile:
      m.tensile_stiffness_u_N_m *= factor;
      m.tensile_stiffness_v_N_m *= factor;
      return;
    case MaterialParameter::kBending:
      m.bending_rigidity_u_Nm *= factor;
      m.bending_rigidity_v_Nm *= factor;
      return;
    default: set_parameter(m, parameter, factor * get_parameter(m, parameter));
  }
}

std::string_view parameter_name(MaterialParameter parameter) {
  switch (parameter) {
    case MaterialParameter::kTensile: return "tensile_N_m";
    case MaterialParameter::kTensileU: return "tensile_u_N_m";
    case MaterialParameter::kTensileV: return "tensile_v_N_m";
    case MaterialParameter::kShear: return "shear_N_m";
    case MaterialParameter::kBending: return "bending_Nm";
    case MaterialParameter::kBendingU: return "bending_u_Nm";
    case MaterialParameter::kBendingV: return "bending_v_Nm";
    case MaterialParameter::kSurfaceDensity: return "surface_density_kg_m2";
    case MaterialParameter::kBendingCoupling: return "bending_coupling_ratio";
    case MaterialParameter::kTwist: return "twist_ratio";
    case MaterialParameter::kRestCurvatureUU: return "rest_curvature_uu_1_m";
    case MaterialParameter::kRestCurvatureVV: return "rest_curvature_vv_1_m";
    case MaterialParameter::kRestCurvatureUV: return "rest_curvature_uv_1_m";
    case MaterialParameter::kBendingStiffening: return "bending_stiffening_m2";
    case MaterialParameter::kMarkerMass: return "marker_mass_kg";
    case MaterialParameter::kRelaxationFraction: return "relaxation_fraction";
    case MaterialParameter::kRelaxationTime: return "relaxation_time_s";
    case MaterialParameter::kClampGripStrength: return "clamp_grip_strength";
    case MaterialParameter::kClampGripWidth: return "clamp_grip_width_m";
    case MaterialParameter::kClampSlipCompliance: return "clamp_slip_compliance_m_N";
  }
  throw std::invalid_argument("parameter_name: unknown MaterialParameter " +
                              std::to_string(static_cast<int>(parameter)));
}

ParameterScale parameter_scale(MaterialParameter parameter) {
  switch (parameter) {
    case MaterialParameter::kTensile:
    case MaterialParameter::kTensileU:
    case MaterialParameter::kTensileV:
    case MaterialParameter::kShear: return {true, 1.0, 1.0, 1e7};            // N/m
    case MaterialParameter::kBending:
    case MaterialParameter::kBendingU:
    case MaterialParameter::kBendingV: return {true, 1.0, 1e-8, 1.0};        // N*m
    case MaterialParameter::kSurfaceDensity: return {true, 1.0, 1e-3, 10.0};  // kg/m^2
    // Ratios to sqrt(D_u D_v): |D12| < sqrt(D_u D_v) keeps the plate stable; an isotropic plate
    // has D66 / D = (1 - nu)/2, a woven fabric's twist can be far softer.
    case MaterialParameter::kBendingCoupling: return {false, 0.1, -0.95, 0.95};
    case MaterialParameter::kTwist: return {true, 1.0, 1e-3, 10.0};
    // A roll set tighter than a 5 cm radius is a crease, not a set.
    case MaterialParameter::kRestCurvatureUU:
    case MaterialParameter::kRestCurvatureVV:
    case MaterialParameter::kRestCurvatureUV: return {false, 1.0, -20.0, 20.0};  // 1/m
    // beta kappa^2 = 1 at kappa = 10 1/m for beta = 0.01 m^2.
    case MaterialParameter::kBendingStiffening: return {false, 0.01, 0.0, 10.0};  // m^2
    case MaterialParameter::kMarkerMass: return {false, 1e-3, 0.0, 0.05};         // kg
    case MaterialParameter::kRelaxationFraction: return {false, 0.1, 0.0, 0.95};
    case MaterialParameter::kRelaxationTime: return {true, 1.0, 0.1, 1e6};        // s
    // Strength 1 holds a vertex as firmly as the clamp's own patch; 10x that is rigid for any
    // sheet the twin simulates.
    case MaterialParameter::kClampGripStrength: return {false, 0.1, 0.0, 10.0};
    case MaterialParameter::kClampGripWidth: return {true, 1.0, 0.005, kMaxClampGripWidth_m};  // m
    // 1 cm of slip per newton: a clamp holding a 1 m ply by a corner carries a few newtons.
    case MaterialParameter::kClampSlipCompliance: return {false, 0.01, 0.0, kMaxClampSlipCompliance_m_N};  // m/N
  }
  throw std::invalid_argument("parameter_scale: unknown MaterialParameter " +
                              std::to_string(static_cast<int>(parameter)));
}

double to_search_coordinate(MaterialParameter parameter, double value) {
  const ParameterScale s = parameter_scale(parameter);
  return s.logarithmic ? std::log(value) : value / s.scale;
}

double from_search_coordinate(MaterialParameter parameter, double coordinate) {
  const ParameterScale s = parameter_scale(parameter);
  return s.logarithmic ? std::exp(coordinate) : coordinate * s.scale;
}

double value_per_search_coordinate(MaterialParameter parameter, double value) {
  const ParameterScale s = parameter_scale(parameter);
  return s.logarithmic ? value : s.scale;
}

MaterialParameter parse_material_parameter(std::string_view name) {
  std::string valid;
  for (MaterialParameter p : kAllMaterialParameters) {
    if (parameter_name(p) == name) return p;
    valid += (valid.empty() ? "" : ", ") + std::string(parameter_name(p));
  }
  throw std::invalid_argument("unknown material parameter '" + std::string(name) +
                              "'; expected one of: " + valid);
}

}  // namespace twin
