#include "twin/mesh/mesh_io.h"
#include "tests/support/temp_dir.h"

#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

namespace twin::mesh_io_test {
namespace {

namespace fs = std::filesystem;

// Each test case's files go to a fresh directory of its own.
class TempDir : public testing_support::TempDir {
 public:
  TempDir() : testing_support::TempDir("twin_mesh_io_test") {}
};

void write_file(const fs::path& path, const std::string& bytes) { testing_support::write_file(path, bytes); }

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A small curved mesh with awkward (non-decimal) coordinates, seeded.
SurfaceMesh awkward_mesh(bool with_uv) {
  const SheetMesh sheet = make_rectangular_sheet(0.3, 0.2, 0.07);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  SurfaceMesh mesh;
  for (const Vec2& uv : sheet.rest_uv) {
    mesh.positions.emplace_back(uv.x() / 3.0 + jitter(rng), uv.y() * M_PI + jitter(rng),
                                std::sin(uv.x()) * 1e-7 + jitter(rng));
  }
  mesh.triangles = sheet.triangles;
  if (with_uv) mesh.uv = sheet.rest_uv;
  return mesh;
}

void check_same_topology(const SurfaceMesh& a, const SurfaceMesh& b) {
  REQUIRE(a.positions.size() == b.positions.size());
  REQUIRE(a.uv.size() == b.uv.size());
  CHECK(a.triangles == b.triangles);
}

TEST_CASE("binary PLY round-trips bit-exactly with uv and scalars", "[twin][mesh_io]") {
  TempDir dir;
  for (bool with_uv : {false, true}) {
    const SurfaceMesh mesh = awkward_mesh(with_uv);
    std::vector<double> error(mesh.positions.size());
    for (std::size_t i = 0; i < error.size(); ++i) error[i] = 1e-3 / (1.0 + i);
    const fs::path path = dir / "mesh.ply";
    write_ply(path, mesh, {{"error_m", error}, {"weight", error}}, /*binary=*/true);
    CHECK(read_file(path).find("property double error_m\nproperty double weight\n") !=
          std::string::npos);
    const SurfaceMesh back = read_surface_mesh(path);
    check_same_topology(mesh, back);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      CHECK(std::memcmp(mesh.positions[i].data(), back.positions[i].data(), 24) == 0);
      if (with_uv) CHECK(std::memcmp(mesh.uv[i].data(), back.uv[i].data(), 16) == 0);
    }
  }
}

TEST_CASE("ASCII PLY and OBJ round-trip to 1e-12 relative", "[twin][mesh_io]") {
  TempDir dir;
  for (const char* name : {"mesh.ply", "mesh.OBJ", "scalars.ply"}) {
    for (bool with_uv : {false, true}) {
      const SurfaceMesh mesh = awkward_mesh(with_uv);
      const fs::path path = dir / name;
      if (std::string(name) == "scalars.ply") {
        write_ply(path, mesh, {{"error_m", std::vector<double>(mesh.positions.size(), 0.1)}});
      } else {
        write_surface_mesh(path, mesh);
      }
      const SurfaceMesh back = read_surface_mesh(path);
      check_same_topology(mesh, back);
      for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        CHECK((mesh.positions[i] - back.positions[i]).norm() <= 1e-12 * mesh.positions[i].norm());
        if (with_uv) CHECK((mesh.uv[i] - back.uv[i]).norm() <= 1e-12 * mesh.uv[i].norm());
      }
    }
  }
}

TEST_CASE("OBJ reader handles quads, negative indices and texture forms", "[twin][mesh_io]") {
  TempDir dir;
  const fs::path path = dir / "quad.obj";
  write_file(path,
             "# two quads sharing an edge\r\nmtllib a.mtl\no sheet\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0\nvt 2 1\nvn 0 0 1\ns off\nusemtl m\n"
             "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
             "f -5/-5 -2/-2 -1/-1 -4/-4  # relative\n");
  const SurfaceMesh mesh = read_surface_mesh(path);
  REQUIRE(mesh.positions.size() == 6);
  REQUIRE(mesh.triangles.size() == 4);
  CHECK(mesh.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(mesh.triangles[1] == std::array<int, 3>{0, 2, 3});
  CHECK(mesh.triangles[2] == std::array<int, 3>{1, 4, 5});
  CHECK(mesh.triangles[3] == std::array<int, 3>{1, 5, 2});
  REQUIRE(mesh.uv.size() == 6);
  CHECK(mesh.uv[4] == Vec2(2, 0));

  // Faces without vt (a//c) leave uv empty.
  write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
  const SurfaceMesh plain = read_surface_mesh(path);
  CHECK(plain.triangles.size() == 1);
  CHECK(plain.uv.empty());
}

TEST_CASE("PLY reader skips extra properties and elements in any order", "[twin][mesh_io]") {
  TempDir dir;
  const fs::path ascii = dir / "extra.PLY";
  write_file(ascii,
             "ply\nformat ascii 1.0\ncomment made by hand\n"
             "element material 1\nproperty list uchar float colours\nproperty int id\n"
             "element face 1\nproperty uchar flags\nproperty list uchar uint vertex_index\n"
             "element vertex 4\nproperty float nx\nproperty double x\nproperty float y\n"
             "property short z\nproperty uchar red\nproperty float s\nproperty float t\n"
             "end_header\n"
             "3 0.1 0.2 0.3 7\n"
             "9 4 0 1 2 3\n"
             "0 0 0 0 255 0 0\n0 1.5 0 0 255 1 0\n0 1.5 1 0 255 1 1\n1 0 1 -2 255 0 1\n");
  const SurfaceMesh mesh = read_surface_mesh(ascii);
  REQUIRE(mesh.positions.size() == 4);
  CHECK(mesh.positions[1] == Vec3(1.5, 0, 0));
  CHECK(mesh.positions[3] == Vec3(0, 1, -2));
  REQUIRE(mesh.triangles.size() == 2);
  CHECK(mesh.triangles[1] == std::array<int, 3>{0, 2, 3});
  REQUIRE(mesh.uv.size() == 4);
  CHECK(mesh.uv[2] == Vec2(1, 1));

  // Big-endian binary: an extra element with a list before the vertices, float positions.
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nelement edge 2\nproperty list ushort int verts\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar quality\nelement face 1\nproperty list int short vertex_indices\n"
      "end_header\n";
  auto put = [&bytes](auto value) {
    char b[sizeof(value)];
    std::memcpy(b, &value, sizeof(value));
    if constexpr (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(value));
    bytes.append(b, sizeof(value));
  };
  put(std::uint16_t{2});
  put(std::int32_t{0});
  put(std::int32_t{1});
  put(std::uint16_t{1});
  put(std::int32_t{2});
  const float xyz[3][3] = {{0, 0, 0.5f}, {2, 0, 0.5f}, {0, 3, 0.5f}};
  for (const auto& p : xyz) {
    for (float v : p) put(v);
    put(std::uint8_t{200});
  }
  put(std::int32_t{3});
  put(std::int16_t{0});
  put(std::int16_t{1});
  put(std::int16_t{2});
  const fs::path binary = dir / "big.ply";
  write_file(binary, bytes);
  const SurfaceMesh big = read_surface_mesh(binary);
  REQUIRE(big.positions.size() == 3);
  CHECK(big.positions[2] == Vec3(0, 3, 0.5));
  REQUIRE(big.triangles.size() == 1);
  CHECK(big.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(big.uv.empty());
}

TEST_CASE("malformed files throw naming the line or element", "[twin][mesh_io]") {
  TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const fs::path ply = dir / "bad.ply";
  const fs::path obj = dir / "bad.obj";
  const std::string ply_path = ply.string();

  write_file(ply, header + "0 0 0\n1 0 0\n0 abc 0\n3 0 1 2\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(ply_path + ":12: ") &&
                                                Catch::Contains("expected a number for 'y'") &&
                                                Catch::Contains("'abc'"));
  write_file(ply, header + "0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply),
                    Catch::Contains(":12: ") && Catch::Contains("not finite"));
  write_file(ply, header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(":13: element face 0") &&
                                                Catch::Contains("index 3 is out of range"));
  write_file(ply, header + "0 0 0\n1 0 0\n0 1 0\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(":13: file ends early"));
  write_file(ply, header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(":14: data after the last element"));
  write_file(ply, header + "0 0 0\n1 0 0 5\n0 1 0\n3 0 1 2\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(":11: element vertex 1: more values"));
  write_file(ply,
             "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\n"
             "end_header\n0 0\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(ply_path + ":3: ") &&
                                                Catch::Contains("no scalar property 'x'"));
  write_file(ply, "ply\nformat ascii 2.0\nend_header\n");
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(":2: expected 'format"));

  SurfaceMesh mesh = awkward_mesh(false);
  write_ply(ply, mesh, {}, /*binary=*/true);
  std::string bytes = read_file(ply);
  write_file(ply, bytes.substr(0, bytes.size() - 5));
  CHECK_THROWS_WITH(
      read_surface_mesh(ply),
      Catch::Contains(ply_path + ": element face " + std::to_string(mesh.triangles.size() - 1)) &&
          Catch::Contains("truncated"));
  const std::size_t vertex_data = bytes.find("end_header\n") + 11;
  write_file(ply, bytes.substr(0, vertex_data + 24 * 2 + 10));
  CHECK_THROWS_WITH(read_surface_mesh(ply), Catch::Contains(ply_path + ": element vertex 2 of ") &&
                                                Catch::Contains("property 'y'"));
  mesh.positions[4].z() = std::numeric_limits<double>::infinity();
  write_ply(ply, mesh, {}, /*binary=*/true);
  CHECK_THROWS_WITH(read_surface_mesh(ply),
                    Catch::Contains(": element vertex 4 of ") && Catch::Contains("not finite"));

  write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n");
  CHECK_THROWS_WITH(read_surface_mesh(obj), Catch::Contains(obj.string() + ":5: ") &&
                                                Catch::Contains("vertex index 4 is out of range"));
  write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n");
  CHECK_THROWS_WITH(read_surface_mesh(obj), Catch::Contains(":4: vertex index -4 is out of range"));
  write_file(obj, "v 0 0 0\nv 1 x 0\n");
  CHECK_THROWS_WITH(read_surface_mesh(obj),
                    Catch::Contains(":2: expected a finite number") && Catch::Contains("'x'"));
  write_file(obj, "v 0 0 0\nv 1 0 NaN\n");
  CHECK_THROWS_WITH(read_surface_mesh(obj), Catch::Contains(":2: expected a finite number"));
  write_file(obj,
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 5 5\n"
             "f 1/1 2/2 3/3\nf 2/4 4/2 3/3\n");
  CHECK_THROWS_WITH(read_surface_mesh(obj),
                    Catch::Contains(":10: vertex 2 has two different texture coordinates"));
  write_file(obj, "v 0 0 0\nv 1 0 0\nf 1 2\n");
  CHECK_THROWS_WITH(read_surface_mesh(obj), Catch::Contains(":3: expected a face"));
  CHECK_THROWS_WITH(read_surface_mesh(dir / "mesh.stl"), Catch::Contains("unknown mesh extension"));
  CHECK_THROWS_WITH(read_surface_mesh(dir / "missing.obj"), Catch::Contains("cannot open"));
}

TEST_CASE("a failed write leaves the existing file untouched", "[twin][mesh_io]") {
  TempDir dir;
  const fs::path path = dir / "keep.ply";
  write_file(path, "original contents\n");
  const SurfaceMesh mesh = awkward_mesh(true);
  CHECK_THROWS_WITH(write_ply(path, mesh, {{"error_m", {1.0, 2.0}}}),
                    Catch::Contains(path.string()) && Catch::Contains("'error_m' has 2 values"));
  CHECK_THROWS_WITH(write_ply(path, mesh, {{"x", std::vector<double>(mesh.positions.size())}}),
                    Catch::Contains("already used"));
  SurfaceMesh bad_uv = mesh;
  bad_uv.uv.pop_back();
  CHECK_THROWS_AS(write_obj(dir / "keep.obj", bad_uv), std::invalid_argument);
  CHECK(read_file(path) == "original contents\n");
  CHECK_FALSE(fs::exists(dir / "keep.ply.tmp"));
  CHECK_THROWS_WITH(write_ply(dir / "no_such_dir" / "m.ply", mesh), Catch::Contains("cannot open"));

  // A successful write replaces the file and leaves no temporary behind.
  write_ply(path, mesh);
  CHECK(read_surface_mesh(path).positions.size() == mesh.positions.size());
  CHECK_FALSE(fs::exists(dir / "keep.ply.tmp"));
}

TEST_CASE("header counts that the file cannot hold are refused before allocating",
          "[twin][mesh_io]") {
  TempDir dir;
  const fs::path huge = dir / "huge.ply";
  write_file(huge,
             "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
             "property float x\nproperty float y\nproperty float z\nend_header\n");
  CHECK_THROWS_WITH(read_surface_mesh(huge), Catch::Contains("huge.ply") &&
                                                 Catch::Contains("more elements than"));
  const fs::path empty = dir / "empty.ply";
  write_file(empty,
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement junk 1000000000000000000\nelement face 1\n"
             "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  CHECK_THROWS_WITH(read_surface_mesh(empty), Catch::Contains("empty.ply:7") &&
                                                  Catch::Contains("no properties"));
}

}  // namespace
}  // namespace twin::mesh_io_test
