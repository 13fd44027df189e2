// Display reconstruction: the GP3 mesh of a sampled sheet lies on the sheet and covers it; PLY
// output is readable and a bad path is reported.
#include <catch2/catch.hpp>

#include <fstream>
#include <random>

#include "tests/support/temp_dir.h"
#include "tests/tracking/analytic_scene.h"
#include "tracking/cloud_surface.h"

namespace tracking {

TEST_CASE("reconstructed display mesh lies on the sheet and covers it",
          "[tracker][reconstruction]") {
  testing::SheetShape shape;
  const testing::SaggingSheet sheet(shape, {0, 0, 0});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  std::vector<Eigen::Vector3f> points;
  for (double x = -0.58; x <= 0.58; x += 0.012) {
    for (double y = -0.48; y <= 0.48; y += 0.012) {
      const double px = x + jitter(rng), py = y + jitter(rng);
      points.emplace_back(px, py, shape.height_at(px, py));
    }
  }
  const SurfaceMesh mesh = reconstruct_surface(points, ReconstructionOptions{});
  REQUIRE(mesh.triangles.size() > points.size());  // about two triangles per point when closed
  CHECK(validate_mesh(mesh).empty());
  double area = 0.0;
  for (double a : vertex_areas(mesh.vertices_m, mesh.triangles)) area += a;
  // The curved sheet's area is a little above its 1.16 x 0.96 m footprint; holes would lower it.
  CHECK(area > 0.9 * 1.16 * 0.96);
  CHECK(area < 1.2 * 1.16 * 0.96);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Vec3 centre = (mesh.vertices_m[t[0]] + mesh.vertices_m[t[1]] + mesh.vertices_m[t[2]]) / 3;
    CHECK(sheet.distance(centre) < 0.002);  // chords of a gently curved sheet
  }
  CHECK(reconstruct_surface({}, ReconstructionOptions{}).triangles.empty());
}

TEST_CASE("PLY output of a mesh", "[tracker][reconstruction]") {
  testing_support::TempDir dir("tracker_ply");
  const SurfaceMesh mesh = make_grid_mesh(1.0, 0.5, 3, 2);
  const std::string path = (dir / "surface.ply").string();
  write_ply(path, mesh);
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text.rfind("ply\nformat ascii 1.0\n", 0) == 0);
  CHECK(text.find("element vertex 6\n") != std::string::npos);
  CHECK(text.find("element face 4\n") != std::string::npos);
  CHECK(text.find("-0.500000 -0.250000 0.000000\n") != std::string::npos);
  CHECK(text.find("3 0 1 4\n") != std::string::npos);
  CHECK_THROWS_WITH(write_ply((dir / "missing" / "x.ply").string(), mesh),
                    Catch::Contains("missing/x.ply"));
}

}  // namespace tracking
