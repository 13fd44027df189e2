#include "twin/mesh/mesh_refinement.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace twin {
namespace {

// Sum of the lengths of edges used by one triangle only. A hanging vertex (a vertex in the middle
// of a neighbour's edge) leaves its two half edges and the neighbour's whole edge unshared, so
// the boundary comes out longer than the sheet's perimeter.
double boundary_length(const SheetMesh& mesh) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  double length = 0.0;
  for (const auto& [edge, count] : uses) {
    REQUIRE(count <= 2);
    if (count == 1) length += (mesh.rest_uv[edge.first] - mesh.rest_uv[edge.second]).norm();
  }
  return length;
}

double longest_edge(const SheetMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  double longest = 0.0;
  for (int k = 0; k < 3; ++k) {
    longest = std::max(longest, (mesh.rest_uv[tri[k]] - mesh.rest_uv[tri[(k + 1) % 3]]).norm());
  }
  return longest;
}

Vec2 centroid(const SheetMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  return (mesh.rest_uv[tri[0]] + mesh.rest_uv[tri[1]] + mesh.rest_uv[tri[2]]) / 3.0;
}

TEST_CASE("refinement near points halves the edges there, keeps the sheet whole and the rest alone",
          "[twin][mesh]") {
  const double w = 1.17, h = 0.975, edge = 0.06;
  const SheetMesh coarse = make_rectangular_sheet(w, h, edge);
  const std::vector<Vec2> clamps = {{0.11, 0.02}, {1.15, 0.17}, {0.6, 0.5}};
  const SheetMesh one = refine_near_points(coarse, clamps, {0.15});
  const SheetMesh two = refine_near_points(coarse, clamps, {0.25, 0.08});

  for (const SheetMesh* mesh : {&one, &two}) {
    REQUIRE_NOTHROW(validate_sheet_mesh(*mesh));
    CHECK(mesh->total_rest_area() == Approx(w * h).epsilon(1e-12));
    CHECK(boundary_length(*mesh) == Approx(2.0 * (w + h)).epsilon(1e-12));
    // Old vertices keep their indices.
    for (int i = 0; i < coarse.vertex_count(); ++i) CHECK(mesh->rest_uv[i] == coarse.rest_uv[i]);
  }
  CHECK(one.triangle_count() > coarse.triangle_count());
  CHECK(two.triangle_count() > one.triangle_count());

  auto distance_to_clamps = [&](const Vec2& p) {
    double d = 1e9;
    for (const Vec2& c : clamps) d = std::min(d, (p - c).norm());
    return d;
  };
  const double coarse_longest = [&] {
    double l = 0.0;
    for (int t = 0; t < coarse.triangle_count(); ++t) l = std::max(l, longest_edge(coarse, t));
    return l;
  }();
  int near = 0, far = 0;
  for (int t = 0; t < two.triangle_count(); ++t) {
    const double d = distance_to_clamps(centroid(two, t));
    if (d < 0.05) {
      ++near;
      CHECK(longest_edge(two, t) <= 0.25 * coarse_longest + 1e-12);  // two levels: a quarter
    } else if (d > 0.25 + 2.0 * coarse_longest) {
      ++far;
      CHECK(longest_edge(two, t) > 0.5 * coarse_longest);  // untouched coarse triangles
    }
  }
  CHECK(near > 20);
  CHECK(far > 100);
}

TEST_CASE("refinement with no points or zero levels returns the mesh", "[twin][mesh]") {
  const SheetMesh coarse = make_rectangular_sheet(0.5, 0.4, 0.05);
  CHECK(refine_near_points(coarse, {}, {0.1}).triangle_count() == coarse.triangle_count());
  CHECK(refine_near_points(coarse, {{0.2, 0.2}}, {}).triangle_count() == coarse.triangle_count());
}

TEST_CASE("refinement rejects a negative or non-finite radius, naming the level", "[twin][mesh]") {
  const SheetMesh coarse = make_rectangular_sheet(0.5, 0.4, 0.05);
  CHECK_THROWS_WITH(refine_near_points(coarse, {{0.2, 0.2}}, {0.1, -0.01}),
                    Catch::Contains("level 2") && Catch::Contains("radius_m"));
  CHECK_THROWS_AS(refine_near_points(coarse, {{0.2, 0.2}}, {std::nan("")}), std::invalid_argument);
}

}  // namespace
}  // namespace twin
