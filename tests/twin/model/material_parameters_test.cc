// Names, get/set and scaling of the identifiable material parameters.

#include "twin/model/material_parameters.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <string>

namespace twin {
namespace {

Material orthotropic() {
  Material m;
  m.tensile_stiffness_u_N_m = 8000.0;
  m.tensile_stiffness_v_N_m = 3000.0;
  m.shear_stiffness_N_m = 1200.0;
  m.bending_rigidity_u_Nm = 2e-3;
  m.bending_rigidity_v_Nm = 1e-3;
  m.surface_density_kg_m2 = 0.25;
  return m;
}

TEST_CASE("material parameter names round-trip and are distinct", "[twin][material][sensitivity]") {
  std::set<std::string> names;
  for (MaterialParameter p : kAllMaterialParameters) {
    CHECK(parse_material_parameter(parameter_name(p)) == p);
    names.insert(std::string(parameter_name(p)));
  }
  CHECK(names.size() == kAllMaterialParameters.size());
  CHECK(parameter_name(MaterialParameter::kTensile) == "tensile_N_m");
  CHECK(parameter_name(MaterialParameter::kShear) == "shear_N_m");
  CHECK(parameter_name(MaterialParameter::kBending) == "bending_Nm");
}

TEST_CASE("an unknown parameter name is rejected with the valid names",
          "[twin][material][sensitivity]") {
  try {
    parse_material_parameter("youngs_modulus");
    FAIL("expected std::invalid_argument");
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    CHECK(what.find("'youngs_modulus'") != std::string::npos);
    for (MaterialParameter p : kAllMaterialParameters) {
      CHECK(what.find(std::string(parameter_name(p))) != std::string::npos);
    }
  }
}

TEST_CASE("get, set and scale address the right material fields", "[twin][material][sensitivity]") {
  const Material base = orthotropic();
  // Paired parameters read the u value and set both.
  CHECK(get_parameter(base, MaterialParameter::kTensile) == 8000.0);
  CHECK(get_parameter(base, MaterialParameter::kTensileV) == 3000.0);
  CHECK(get_parameter(base, MaterialParameter::kBending) == 2e-3);
  CHECK(get_parameter(base, MaterialParameter::kBendingV) == 1e-3);
  CHECK(get_parameter(base, MaterialParameter::kShear) == 1200.0);
  CHECK(get_parameter(base, MaterialParameter::kSurfaceDensity) == 0.25);

  Material m = base;
  set_parameter(m, MaterialParameter::kTensile, 5000.0);
  CHECK(m.tensile_stiffness_u_N_m == 5000.0);
  CHECK(m.tensile_stiffness_v_N_m == 5000.0);
  set_parameter(m, MaterialParameter::kBendingV, 4e-3);
  CHECK(m.bending_rigidity_u_Nm == 2e-3);
  CHECK(m.bending_rigidity_v_Nm == 4e-3);
  set_parameter(m, MaterialParameter::kSurfaceDensity, 0.5);
  CHECK(m.surface_density_kg_m2 == 0.5);
  CHECK(m.shear_stiffness_N_m == 1200.0);

  // Scaling a pair keeps its ratio; scaling one field touches nothing else.
  m = base;
  scale_parameter(m, MaterialParameter::kTensile, 2.0);
  CHECK(m.tensile_stiffness_u_N_m == 16000.0);
  CHECK(m.tensile_stiffness_v_N_m == 6000.0);
  scale_parameter(m, MaterialParameter::kBending, 0.5);
  CHECK(m.bending_rigidity_u_Nm == 1e-3);
  CHECK(m.bending_rigidity_v_Nm == 5e-4);
  scale_parameter(m, MaterialParameter::kShear, 3.0);
  CHECK(m.shear_stiffness_N_m == 3600.0);
  CHECK(m.surface_density_kg_m2 == 0.25);
}

TEST_CASE("the plate's coupling and twist are ratios to the bending, Huber's until set", "[twin][material]") {
  Material m;
  m.bending_model = Material::BendingModel::kPlate;
  m.poisson_ratio = 0.3;
  CHECK(get_parameter(m, MaterialParameter::kBendingCoupling) == Approx(0.3));
  CHECK(get_parameter(m, MaterialParameter::kTwist) == Approx(0.35));
  set_parameter(m, MaterialParameter::kTwist, 0.05);
  set_parameter(m, MaterialParameter::kBendingCoupling, -0.2);
  scale_parameter(m, MaterialParameter::kBending, 4.0);  // D_u, D_v x4: D66 and D12 follow
  CHECK(get_parameter(m, MaterialParameter::kTwist) == Approx(0.05));
  CHECK(m.twist_rigidity_Nm() == Approx(0.05 * 4e-3));
  CHECK(m.bending_coupling_Nm() == Approx(-0.2 * 4e-3));
  CHECK_NOTHROW(m.validate());
  m.bending_model = Material::BendingModel::kHinge;  // the hinge model has no D12, D66
  CHECK_THROWS_WITH(m.validate(), Catch::Contains("plate"));
}

TEST_CASE("search coordinates: log for stiffnesses, scaled linear for effects", "[twin][material][effects]") {
  for (MaterialParameter p : kAllMaterialParameters) {
    const ParameterScale s = parameter_scale(p);
    INFO(parameter_name(p));
    CHECK(s.lower < s.upper);
    const double mid = s.logarithmic ? std::sqrt(s.lower * s.upper) : 0.5 * (s.lower + s.upper);
    CHECK(from_search_coordinate(p, to_search_coordinate(p, mid)) == Approx(mid).epsilon(1e-12));
    const double h = 1e-6;
    const double y = to_search_coordinate(p, mid);
    const double fd = (from_search_coordinate(p, y + h) - from_search_coordinate(p, y - h)) / (2 * h);
    CHECK(value_per_search_coordinate(p, mid) == Approx(fd).epsilon(1e-6));
  }
  CHECK(parameter_scale(MaterialParameter::kBending).logarithmic);
  CHECK_FALSE(parameter_scale(MaterialParameter::kRestCurvatureUU).logarithmic);
  // The effect parameters address the effects block.
  Material m;
  set_parameter(m, MaterialParameter::kRestCurvatureUV, -0.5);
  set_parameter(m, MaterialParameter::kMarkerMass, 2e-4);
  CHECK(m.effects.rest_curvature_uv_1_m == -0.5);
  CHECK(get_parameter(m, MaterialParameter::kMarkerMass) == 2e-4);
  CHECK(m.effects.any());
}

}  // namespace
}  // namespace twin
