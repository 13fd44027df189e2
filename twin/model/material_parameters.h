#pragma once
// The material parameters that identification estimates, as one enum with names for files and
// command lines. The paper identifies an isotropic sheet (one tensile stiffness, one shear
// stiffness, one bending rigidity); the per-direction ones are there for orthotropic fits.
//
//   kTensile         Y_u and Y_v together (N/m)      "tensile_N_m"
//   kTensileU        Y_u, weft (N/m)                 "tensile_u_N_m"
//   kTensileV        Y_v, warp (N/m)                 "tensile_v_N_m"
//   kShear           G (N/m)                         "shear_N_m"
//   kBending         D_u and D_v together (N*m)      "bending_Nm"
//   kBendingU        D_u, curvature along u (N*m)    "bending_u_Nm"
//   kBendingV        D_v, curvature along v (N*m)    "bending_v_Nm"
//   kSurfaceDensity  rho (kg/m^2)                    "surface_density_kg_m2"
//   kBendingCoupling D12 / sqrt(D_u D_v) (1)         "bending_coupling_ratio"  (plate model)
//   kTwist           D66 / sqrt(D_u D_v) (1)         "twist_ratio"             (plate model)
// and the parameters of the optional effects (model_effects.h):
//   kRestCurvatureUU     K0_uu (1/m)                  "rest_curvature_uu_1_m"
//   kRestCurvatureVV     K0_vv (1/m)                  "rest_curvature_vv_1_m"
//   kRestCurvatureUV     K0_uv (1/m)                  "rest_curvature_uv_1_m"
//   kBendingStiffening   beta (m^2)                   "bending_stiffening_m2"
//   kMarkerMass          point mass per marker (kg)   "marker_mass_kg"
//   kRelaxationFraction  relaxed fraction (1)         "relaxation_fraction"
//   kRelaxationTime      tau (s)                      "relaxation_time_s"
//   kClampGripStrength   grip strength s (1)          "clamp_grip_strength"
//   kClampGripWidth      grip width w (m)             "clamp_grip_width_m"
//   kClampSlipCompliance slip per pull c (m/N)        "clamp_slip_compliance_m_N"
//
// Search coordinates. Optimisers and derivatives work in a coordinate y per parameter: y = log p
// for the positive ones (stiffnesses span decades, and a relative step means the same
// everywhere), y = p / scale for effect parameters that may be zero or negative (their absence
// is p = 0). parameter_scale() says which, with the physical bounds of p.

#include <array>
#include <string>
#include <string_view>

#include "twin/model/material.h"

namespace twin {

enum class MaterialParameter {
  kTensile,
  kTensileU,
  kTensileV,
  kShear,
  kBending,
  kBendingU,
  kBendingV,
  kSurfaceDensity,
  kBendingCoupling,
  kTwist,
  kRestCurvatureUU,
  kRestCurvatureVV,
  kRestCurvatureUV,
  kBendingStiffening,
  kMarkerMass,
  kRelaxationFraction,
  kRelaxationTime,
  kClampGripStrength,
  kClampGripWidth,
  kClampSlipCompliance,
};

inline constexpr std::array<MaterialParameter, 20> kAllMaterialParameters = {
    MaterialParameter::kTensile,          MaterialParameter::kTensileU,
    MaterialParameter::kTensileV,         MaterialParameter::kShear,
    MaterialParameter::kBending,          MaterialParameter::kBendingU,
    MaterialParameter::kBendingV,         MaterialParameter::kSurfaceDensity,
    MaterialParameter::kBendingCoupling,  MaterialParameter::kTwist,
    MaterialParameter::kRestCurvatureUU,  MaterialParameter::kRestCurvatureVV,
    MaterialParameter::kRestCurvatureUV,  MaterialParameter::kBendingStiffening,
    MaterialParameter::kMarkerMass,       MaterialParameter::kRelaxationFraction,
    MaterialParameter::kRelaxationTime,   MaterialParameter::kClampGripStrength,
    MaterialParameter::kClampGripWidth,   MaterialParameter::kClampSlipCompliance};

struct ParameterScale {
  bool logarithmic = true;  // y = log p; else y = p / scale
  double scale = 1.0;       // SI units of p per unit of y (linear parameters only)
  double lower = 0.0;       // physical bounds of p (SI): searches stay inside them
  double upper = 0.0;
};
ParameterScale parameter_scale(MaterialParameter parameter);
double to_search_coordinate(MaterialParameter parameter, double value);
double from_search_coordinate(MaterialParameter parameter, double coordinate);
// dp/dy at p = value: value for a logarithmic parameter, scale for a linear one.
double value_per_search_coordinate(MaterialParameter parameter, double value);

// Value in SI units (see the table above). For the paired kTensile and kBending: the u value
// (equal to the v value on an isotropic sheet, which is what those parameters are for).
double get_parameter(const Material& material, MaterialParameter parameter);

// Sets the value. kTensile and kBending set both directions to `value`. Does not validate (the
// ShellModel does when the material is applied).
void set_parameter(Material& material, MaterialParameter parameter, double value);

// Multiplies the parameter by `factor`; for kTensile and kBending both directions, which keeps
// their ratio. On an isotropic sheet this is set_parameter(factor * get_parameter()); on an
// orthotropic one it is the direction the sensitivities of the paired parameters are taken
// along (equilibrium_sensitivity.h).
void scale_parameter(Material& material, MaterialParameter parameter, double factor);

// Name as in the table above (its unit is part of it).
std::string_view parameter_name(MaterialParameter parameter);

// Inverse of parameter_name. Throws std::invalid_argument quoting `name` and listing the valid
// names.
MaterialParameter parse_material_parameter(std::string_view name);

}  // namespace twin
