#include "twin/mesh/sheet_mesh.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace twin {
namespace {

TEST_CASE("rectangular sheet covers the rectangle with valid CCW triangles", "[twin][mesh]") {
  for (auto pattern : {TriangulationPattern::kOffsetRows, TriangulationPattern::kRightTriangles}) {
    const SheetMesh mesh = make_rectangular_sheet(1.17, 0.975, 0.05, pattern);
    REQUIRE_NOTHROW(validate_sheet_mesh(mesh));
    CHECK(mesh.total_rest_area() == Approx(1.17 * 0.975).epsilon(1e-12));
    for (const Vec2& p : mesh.rest_uv) {
      CHECK(p.x() >= 0.0);
      CHECK(p.x() <= 1.17 + 1e-12);
      CHECK(p.y() >= 0.0);
      CHECK(p.y() <= 0.975 + 1e-12);
    }
  }
}

TEST_CASE("offset rows give near-equilateral triangles away from the side edges", "[twin][mesh]") {
  const double a = 0.02;
  const SheetMesh mesh = make_rectangular_sheet(0.6, 0.5, a);
  int interior = 0;
  for (const auto& tri : mesh.triangles) {
    double shortest = 1e9, longest = 0.0;
    bool touches_side = false;
    for (int k = 0; k < 3; ++k) {
      const Vec2& p = mesh.rest_uv[tri[k]];
      const double len = (mesh.rest_uv[tri[(k + 1) % 3]] - p).norm();
      shortest = std::min(shortest, len);
      longest = std::max(longest, len);
      touches_side |= p.x() < 1e-12 || p.x() > 0.6 - 1e-12;
    }
    if (touches_side) continue;
    ++interior;
    CHECK(longest / shortest < 1.1);
  }
  CHECK(interior > 500);
}

TEST_CASE("triangle count target is met within 10 percent", "[twin][mesh]") {
  for (int target : {1500, 6000, 24000}) {
    const double a = edge_length_for_triangle_count(1.17, 0.975, target);
    const SheetMesh mesh = make_rectangular_sheet(1.17, 0.975, a);
    CHECK(std::abs(mesh.triangle_count() - target) < 0.1 * target);
  }
}

TEST_CASE("invalid sheets are rejected with the cause named", "[twin][mesh]") {
  CHECK_THROWS_WITH(make_rectangular_sheet(-1.0, 1.0, 0.1), Catch::Contains("width_m"));
  CHECK_THROWS_WITH(make_rectangular_sheet(1.0, NAN, 0.1), Catch::Contains("height_m"));
  SheetMesh mesh = make_rectangular_sheet(1.0, 1.0, 0.5);
  std::swap(mesh.triangles[0][0], mesh.triangles[0][1]);
  CHECK_THROWS_WITH(validate_sheet_mesh(mesh), Catch::Contains("clockwise"));
  mesh = make_rectangular_sheet(1.0, 1.0, 0.5);
  mesh.rest_uv.emplace_back(3.0, 3.0);
  CHECK_THROWS_WITH(validate_sheet_mesh(mesh), Catch::Contains("belongs to no triangle"));
}

// Issue 36: a long, thin sheet of modest area passed the area bound, and the offset-row column
// search then ran over about 1e12 column counts (the test timed out before the fix).
TEST_CASE("a sheet too long for its edge length is refused before the mesh search", "[twin][mesh]") {
  CHECK_THROWS_WITH(make_rectangular_sheet(1.0e9, 1.0e-9, 1.0e-3), Catch::Contains("more than 4M triangles"));
  CHECK_THROWS_WITH(make_rectangular_sheet(1.0e-9, 1.0e9, 1.0e-3, TriangulationPattern::kRightTriangles),
                    Catch::Contains("more than 4M triangles"));
  CHECK(make_rectangular_sheet(20.0, 0.01, 0.01).triangle_count() > 0);  // 2000 x 1 cells is fine
}

}  // namespace
}  // namespace twin
