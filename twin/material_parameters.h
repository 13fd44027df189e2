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

#include <array>
#include <string>
#include <string_view>

#include "twin/material.h"

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
};

inline constexpr std::array<MaterialParameter, 8> kAllMaterialParameters = {
    MaterialParameter::kTensile,  MaterialParameter::kTensileU, MaterialParameter::kTensileV,
    MaterialParameter::kShear,    MaterialParameter::kBending,  MaterialParameter::kBendingU,
    MaterialParameter::kBendingV, MaterialParameter::kSurfaceDensity};

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
