// How a trial's twin is meshed (twin/trials/trial.h: TwinMeshSpec): size, refinement near the clamps,
// jaws resolved; and the --clamp-refinement option that chooses it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "twin/trials/clamp_refinement_option.h"
#include "twin/mesh/material_point.h"
#include "twin/trials/trial.h"

namespace twin {
namespace {

// A 0.4 x 0.3 m sheet held at its top corners: A by 1 cm jaws, B by a pin.
Trial clamped_rectangle() {
  Trial t;
  t.sheet.width_m = 0.4;
  t.sheet.height_m = 0.3;
  t.clamps = {{"A", Vec2(0.02, 0.28), 0.01}, {"B", Vec2(0.38, 0.28), 0.0}};
  return t;
}

TEST_CASE("a rectangular trial sheet is meshed to about the asked triangle count", "[twin][trial]") {
  const SheetMesh mesh = trial_sheet_mesh(clamped_rectangle(), 2000);
  CHECK(mesh.triangle_count() > 1500);
  CHECK(mesh.triangle_count() < 2500);
  CHECK(mesh.total_rest_area() == Approx(0.12));
}

TEST_CASE("a trial's twin mesh is refined near its clamps when asked", "[twin][trial]") {
  const Trial trial = clamped_rectangle();
  const SheetMesh plain = trial_sheet_mesh(trial, TwinMeshSpec{500, {}});
  const SheetMesh refined = trial_sheet_mesh(trial, TwinMeshSpec{500, {0.05}});
  CHECK(plain.triangle_count() == trial_sheet_mesh(trial, 500).triangle_count());
  CHECK(refined.triangle_count() > plain.triangle_count());
  CHECK(refined.total_rest_area() == Approx(plain.total_rest_area()).epsilon(1e-12));
  // Every clamp's host triangle is now a quarter of a coarse one (or less).
  const double coarse_area = plain.total_rest_area() / plain.triangle_count();
  for (const ClampSpec& clamp : trial.clamps) {
    const auto host = locate_material_point(refined, clamp.material_point_m);
    REQUIRE(host);
    CHECK(refined.rest_area(host->triangle) < 0.3 * coarse_area);
  }
}

TEST_CASE("a twin mesh that resolves the jaws has edges of at most 0.4 grip radii there", "[twin][trial]") {
  const Trial trial = clamped_rectangle();  // clamp A grips 1 cm; B is a pin
  const SheetMesh plain = trial_sheet_mesh(trial, 500);
  const ClampSpec& jaws = trial.clamps[0];
  const std::vector<double> radii = jaw_refinement_radii_m(plain, jaws);
  // About 2.3 cm edges: three halvings to 0.3 cm, under 0.4 of the 1 cm grip.
  REQUIRE(radii.size() == 3);
  CHECK(radii.back() == Approx(jaws.grip_radius_m));
  const auto host = locate_material_point(plain, jaws.material_point_m);
  REQUIRE(host);
  // Each coarser level reaches twice as far.
  CHECK(radii[1] == Approx(2.0 * radii[2]));
  CHECK(radii[0] == Approx(4.0 * radii[2]));
  CHECK(jaw_refinement_radii_m(plain, trial.clamps[1]).empty());  // a pin has no jaws
  CHECK(jaw_refinement_radii_m(trial_sheet_mesh(trial, 40000), jaws).empty());  // already fine enough (0.26 cm)

  TwinMeshSpec spec{500, {}};
  spec.resolve_jaws = true;
  const SheetMesh refined = trial_sheet_mesh(trial, spec);
  CHECK(refined.total_rest_area() == Approx(plain.total_rest_area()).epsilon(1e-12));
  CHECK(refined.triangle_count() > plain.triangle_count());
  CHECK(refined.triangle_count() < 2 * plain.triangle_count());  // only near A
  // Within the jaws the edges are at most 0.4 grip radii (mean; the longest a little more).
  int inside = 0;
  double edge_sum_m = 0.0, longest_m = 0.0;
  for (const auto& t : refined.triangles) {
    bool touches = false;
    for (int v : t) touches |= (refined.rest_uv[v] - jaws.material_point_m).norm() < jaws.grip_radius_m;
    if (!touches) continue;
    ++inside;
    for (int k = 0; k < 3; ++k) {
      const double e = (refined.rest_uv[t[k]] - refined.rest_uv[t[(k + 1) % 3]]).norm();
      edge_sum_m += e;
      longest_m = std::max(longest_m, e);
    }
  }
  REQUIRE(inside > 20);
  CHECK(edge_sum_m / (3 * inside) <= 0.4 * jaws.grip_radius_m);
  CHECK(longest_m <= 0.5 * jaws.grip_radius_m);
  // Near the pin nothing changed: its host triangle is as large as before.
  const auto pin_before = locate_material_point(plain, trial.clamps[1].material_point_m);
  const auto pin_after = locate_material_point(refined, trial.clamps[1].material_point_m);
  REQUIRE(pin_before);
  REQUIRE(pin_after);
  CHECK(refined.rest_area(pin_after->triangle) == Approx(plain.rest_area(pin_before->triangle)));

  spec.clamp_refinement_radii_m = {0.05};
  CHECK_THROWS_WITH(trial_sheet_mesh(trial, spec), Catch::Contains("not both"));
}

TEST_CASE("a twin mesh for the quadratic membrane is a quarter as many triangles refined uniformly",
          "[twin][trial]") {
  const Trial trial = clamped_rectangle();
  TwinMeshSpec linear{2000, {}};
  linear.resolve_jaws = true;
  TwinMeshSpec quadratic = linear;
  quadratic.quadratic_membrane = true;
  const SheetMesh lin = trial_sheet_mesh(trial, linear);
  const SheetMesh quad = trial_sheet_mesh(trial, quadratic);
  CHECK(lin.quadratic_patches.empty());
  REQUIRE(quad.quadratic_patches.size() * 4 == quad.triangles.size());
  CHECK(quad.total_rest_area() == Approx(lin.total_rest_area()).epsilon(1e-12));
  // About as many vertices away from the jaws, and the jaws resolved as finely (edges of the
  // final mesh at most 0.4 grip radii there, not those of the coarse one).
  CHECK(quad.triangle_count() > 0.7 * lin.triangle_count());
  CHECK(quad.triangle_count() < 1.5 * lin.triangle_count());
  const ClampSpec& jaws = trial.clamps[0];
  double longest_m = 0.0;
  for (const auto& t : quad.triangles) {
    bool touches = false;
    for (int v : t) touches |= (quad.rest_uv[v] - jaws.material_point_m).norm() < jaws.grip_radius_m;
    for (int k = 0; touches && k < 3; ++k) {
      longest_m = std::max(longest_m, (quad.rest_uv[t[k]] - quad.rest_uv[t[(k + 1) % 3]]).norm());
    }
  }
  CHECK(longest_m <= 0.5 * jaws.grip_radius_m);
  CHECK(longest_m > 0.1 * jaws.grip_radius_m);
}

TEST_CASE("the clamp refinement option reads jaws, none or radii and names itself in errors", "[twin][trial]") {
  CHECK(parse_clamp_refinement("jaws").resolve_jaws);
  CHECK(parse_clamp_refinement("jaws").radii_m.empty());
  CHECK_FALSE(parse_clamp_refinement("none").resolve_jaws);
  CHECK(parse_clamp_refinement("none").radii_m.empty());
  const ClampRefinement radii = parse_clamp_refinement("0.15,0.06");
  CHECK_FALSE(radii.resolve_jaws);
  CHECK(radii.radii_m == std::vector<double>{0.15, 0.06});
  CHECK_THROWS_WITH(parse_clamp_refinement("0.1,-2", "--reference-clamp-refinement"),
                    Catch::Contains("--reference-clamp-refinement") && Catch::Contains("'-2'"));
  CHECK_THROWS_WITH(parse_clamp_refinement("Jaws"), Catch::Contains("--clamp-refinement") && Catch::Contains("'Jaws'"));
}

}  // namespace
}  // namespace twin
