#include "twin/mesh/mesh_io.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>

namespace twin {
namespace {

TEST_CASE("sheet_mesh_from_flat recovers a tilted planar sheet", "[twin][mesh_io]") {
  const SheetMesh sheet = make_rectangular_sheet(0.6, 0.4, 0.05);
  const Mat3 rotation =
      (Eigen::AngleAxisd(0.7, Vec3(1, 2, 0.5).normalized()) * Eigen::AngleAxisd(0.3, Vec3::UnitZ()))
          .toRotationMatrix();
  const Vec3 offset(1.25, -0.4, 0.9);
  SurfaceMesh mesh;
  for (const Vec2& uv : sheet.rest_uv)
    mesh.positions.push_back(rotation * Vec3(uv.x(), uv.y(), 0) + offset);
  mesh.triangles = sheet.triangles;

  const SheetMesh flat = sheet_mesh_from_flat(mesh);
  REQUIRE(flat.triangle_count() == sheet.triangle_count());
  CHECK(flat.total_rest_area() == Approx(0.6 * 0.4).epsilon(1e-12));
  for (int t = 0; t < sheet.triangle_count(); ++t) {
    CHECK(flat.rest_area(t) == Approx(sheet.rest_area(t)).epsilon(1e-9));
    for (int k = 0; k < 3; ++k) {
      const int a = flat.triangles[t][k], b = flat.triangles[t][(k + 1) % 3];
      CHECK((flat.rest_uv[a] - flat.rest_uv[b]).norm() ==
            Approx((sheet.rest_uv[a] - sheet.rest_uv[b]).norm()).epsilon(1e-12));
    }
  }

  // The frame convention: normal signed towards +z (so this mesh keeps its CCW triangles),
  // u = world x projected into the plane, v = n x u.
  const Vec3 n = rotation.col(2);
  REQUIRE(n.z() > 0);
  CHECK(flat.triangles == sheet.triangles);
  const Vec3 u = (Vec3::UnitX() - n.x() * n).normalized();
  const Vec3 d = mesh.positions[9] - mesh.positions[0];
  CHECK((flat.rest_uv[9] - flat.rest_uv[0]).x() == Approx(d.dot(u)).epsilon(1e-12));
  CHECK((flat.rest_uv[9] - flat.rest_uv[0]).y() == Approx(d.dot(n.cross(u))).epsilon(1e-12));

  // Mirrored (all clockwise) triangles are flipped to counter-clockwise.
  for (Vec3& p : mesh.positions) p.x() = -p.x();
  CHECK(sheet_mesh_from_flat(mesh).total_rest_area() == Approx(0.24).epsilon(1e-12));

  // Bumping one vertex off the plane is rejected, naming it.
  const Vec3 mirrored_normal(-rotation(0, 2), rotation(1, 2), rotation(2, 2));
  mesh.positions[17] += 1e-3 * mirrored_normal;
  CHECK_THROWS_WITH(sheet_mesh_from_flat(mesh), Catch::Contains("not flat: vertex 17"));
  CHECK_NOTHROW(sheet_mesh_from_flat(mesh, 2e-3));
}

TEST_CASE("sheet_mesh_from_flat keeps x and y of a horizontal mesh and uses uv",
          "[twin][mesh_io]") {
  const SheetMesh sheet = make_rectangular_sheet(0.3, 0.2, 0.05);
  SurfaceMesh mesh;
  for (const Vec2& uv : sheet.rest_uv) mesh.positions.emplace_back(uv.x() + 0.1, uv.y() / 3.0, 0.1);
  mesh.triangles = sheet.triangles;
  const SheetMesh flat = sheet_mesh_from_flat(mesh);
  for (int i = 0; i < flat.vertex_count(); ++i) {
    CHECK(flat.rest_uv[i] == mesh.positions[i].head<2>());
  }

  // With uv the positions may be any unstretched shape: the sheet rolled on a cylinder
  // (radius 0.1 m) round-trips.
  VecX x(3 * sheet.vertex_count());
  for (int i = 0; i < sheet.vertex_count(); ++i) {
    const double v = sheet.rest_uv[i].y();
    vertex(x, i) = Vec3(sheet.rest_uv[i].x(), 0.1 * std::sin(v / 0.1), 0.3 + 0.1 * (1 - std::cos(v / 0.1)));
  }
  const SurfaceMesh draped = surface_from_positions(sheet, x);
  CHECK(draped.positions[5] == vertex(x, 5));
  const SheetMesh from_uv = sheet_mesh_from_flat(draped);
  CHECK(from_uv.rest_uv == sheet.rest_uv);
  CHECK(from_uv.triangles == sheet.triangles);
  CHECK_THROWS_WITH(surface_from_positions(sheet, VecX(6)), Catch::Contains("expected 3 x"));
  // Texture coordinates in [0, 1] instead of metres are refused, not used as a pre-stress.
  SurfaceMesh normalised = draped;
  for (Vec2& uv : normalised.uv) uv = Vec2(uv.x() / 0.3, uv.y() / 0.2);
  CHECK_THROWS_WITH(sheet_mesh_from_flat(normalised), Catch::Contains("must be in metres"));

  // Mixed orientation names a triangle.
  mesh.triangles[3] = {mesh.triangles[3][0], mesh.triangles[3][2], mesh.triangles[3][1]};
  CHECK_THROWS_WITH(sheet_mesh_from_flat(mesh), Catch::Contains("mixed orientation") &&
                                                    Catch::Contains("triangle 3 is clockwise"));
}

}  // namespace
}  // namespace twin
