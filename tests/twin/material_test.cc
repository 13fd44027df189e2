#include "twin/material.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace twin {
namespace {

using nlohmann::json;

json composite() {
  return json::parse(R"({
    "name": "composite", "surface_density_kg_m2": 0.3, "tensile_stiffness_N_m": 5000,
    "shear_stiffness_N_m": 2942.93, "poisson_ratio": 0.3, "thickness_m": 0.0003,
    "bending_modulus_Pa": 4.77682e7})");
}

TEST_CASE("bending given as a modulus is converted to plate rigidity", "[twin][material]") {
  const Material m = material_from_json(composite(), "composite.json");
  // D = E t^3 / (12 (1 - nu^2)) = 4.77682e7 * 2.7e-11 / 10.92
  CHECK(m.bending_rigidity_u_Nm == Approx(4.77682e7 * 2.7e-11 / 10.92).epsilon(1e-12));
  CHECK(m.bending_rigidity_v_Nm == m.bending_rigidity_u_Nm);
  CHECK(m.bending_given_as_modulus());
  const json written = material_to_json(m);
  CHECK(written["bending_given_as"] == "modulus");
  CHECK(written["bending_modulus_Pa"].get<double>() == 4.77682e7);
  // Round trip keeps the values and the form.
  const Material again = material_from_json(written, "written");
  CHECK(again.bending_rigidity_u_Nm == Approx(m.bending_rigidity_u_Nm).epsilon(1e-15));
}

TEST_CASE("warp and weft values may differ", "[twin][material]") {
  json j = composite();
  j.erase("bending_modulus_Pa");
  j["bending_rigidity_Nm"] = {{"weft", 2e-3}, {"warp", 1e-3}};
  j["tensile_stiffness_N_m"] = {{"weft", 8000}, {"warp", 3000}};
  const Material m = material_from_json(j, "m.json");
  CHECK(m.bending_rigidity_u_Nm == 2e-3);
  CHECK(m.bending_rigidity_v_Nm == 1e-3);
  const Mat3 c = m.membrane_stiffness();
  CHECK(c(0, 1) == Approx(c(1, 0)));
  CHECK(c(0, 0) > c(1, 1));
  CHECK(material_to_json(m)["bending_rigidity_Nm"]["warp"].get<double>() == 1e-3);
}

TEST_CASE("bad material values are rejected with the file and field named", "[twin][material]") {
  struct Case {
    const char* field;
    json value;
    const char* expect;
  };
  const Case cases[] = {
      {"shear_stiffness_N_m", -5.0, "'shear_stiffness_N_m' must be a positive"},
      {"surface_density_kg_m2", 0.0, "'surface_density_kg_m2' must be a positive"},
      {"tensile_stiffness_N_m", "stiff", "'tensile_stiffness_N_m' must be a number"},
      {"poisson_ratio", 1.5, "'poisson_ratio'"},
      {"bending_modulus_Pa", -1.0, "'bending_modulus_Pa' must be positive"},
      {"bending_rigidty_Nm", 1e-3, "'bending_rigidty_Nm' is not a known field"},
  };
  for (const Case& c : cases) {
    json j = composite();
    j[c.field] = c.value;
    INFO(c.field);
    CHECK_THROWS_WITH(material_from_json(j, "prepreg.json"),
                      Catch::Contains("prepreg.json") && Catch::Contains(c.expect));
  }
  json nan_value = composite();
  nan_value["shear_stiffness_N_m"] = std::nan("");  // nlohmann writes NaN as null
  CHECK_THROWS_WITH(material_from_json(nan_value, "f.json"), Catch::Contains("shear_stiffness_N_m"));
  json no_thickness = composite();
  no_thickness.erase("thickness_m");
  CHECK_THROWS_WITH(material_from_json(no_thickness, "f.json"),
                    Catch::Contains("'thickness_m' is needed to convert"));
  json both = composite();
  both["bending_rigidity_Nm"] = 1e-3;
  CHECK_THROWS_WITH(material_from_json(both, "f.json"), Catch::Contains("exactly one"));
  json neither = composite();
  neither.erase("bending_modulus_Pa");
  CHECK_THROWS_WITH(material_from_json(neither, "f.json"),
                    Catch::Contains("'bending_rigidity_Nm' or 'bending_modulus_Pa'"));
  json wrong_form = composite();
  wrong_form["bending_given_as"] = "rigidity";
  CHECK_THROWS_WITH(material_from_json(wrong_form, "f.json"), Catch::Contains("'bending_given_as'"));
}

TEST_CASE("material files are read, written atomically and reported by path", "[twin][material]") {
  const auto dir = std::filesystem::temp_directory_path() / "twin_material_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "m.json").string();
  write_material_file(path, material_from_json(composite(), "composite"));
  CHECK(read_material_file(path).shear_stiffness_N_m == 2942.93);
  {
    std::ofstream(dir / "broken.json") << "{ \"name\": ";
  }
  CHECK_THROWS_WITH(read_material_file((dir / "broken.json").string()),
                    Catch::Contains("broken.json") && Catch::Contains("not valid JSON"));
  CHECK_THROWS_WITH(read_material_file((dir / "missing.json").string()),
                    Catch::Contains("missing.json") && Catch::Contains("cannot open"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace twin
