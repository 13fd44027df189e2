#include "twin/material_parameters.h"

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
  }
  throw std::invalid_argument("parameter_name: unknown MaterialParameter " +
                              std::to_string(static_cast<int>(parameter)));
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
