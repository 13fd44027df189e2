#include "twin/trials/trial.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "twin/mesh/mesh_io.h"
#include "tests/support/temp_dir.h"

namespace twin::trial_test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// Each test case's files go to a fresh directory of its own.
class TempDir : public testing_support::TempDir {
 public:
  TempDir() : testing_support::TempDir("twin_trial_test") {}
};

void write_text(const fs::path& path, const std::string& bytes) { testing_support::write_file(path, bytes); }

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

json read_json(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

void write_json(const fs::path& path, const json& j) { write_text(path, j.dump(2)); }

ClampPose held_at(double x, double y, double z) {
  ClampPose p;
  p.position_m = Vec3(x, y, z);
  return p;
}

ClampPose released() {
  ClampPose p;
  p.engaged = false;
  return p;
}

// A 0.4 x 0.3 m sheet with a 3 x 4 marker grid and two clamps at its top corners, through three
// stages: both held (two markers unseen), A released, and a cloud-only stage. Coordinates are
// awkward (thirds) so that printing them with too few digits would show.
Trial small_trial() {
  Trial t;
  t.material_name = "composite";
  t.sheet.width_m = 0.4;
  t.sheet.height_m = 0.3;
  t.thickness_m = 0.0003;
  t.mass_kg = 0.036;
  t.surface_density_kg_m2 = 0.3;
  t.marker_grid_rows = 3;
  t.marker_grid_cols = 4;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) t.marker_uv_m.push_back(Vec2(0.05 + c * 0.1, 0.05 + r * 0.1));
  }
  t.clamps = {{"A", Vec2(0.02, 0.28), 0.01}, {"B", Vec2(0.38, 0.28), 0.0}};

  TrialStage hold;
  hold.id = "1";
  hold.time_s = 0.0;
  hold.poses = {held_at(0.0, 0.0, 1.0), held_at(1.0 / 3.0, 0.0, 1.0)};
  hold.markers_file = "first.xyz";
  for (int i = 0; i < 12; ++i) {
    hold.observed.markers_m.push_back(Vec3(i / 30.0, 1.0 / 7.0, 1.0 - i / 90.0));
  }
  hold.observed.markers_m[0].setConstant(kNaN);
  hold.observed.markers_m[5].setConstant(kNaN);

  TrialStage release;
  release.id = "2";
  release.time_s = 2.5;
  release.poses = {released(), held_at(0.3, 0.05, 1.1)};
  for (int i = 0; i < 12; ++i) {
    release.observed.markers_m.push_back(Vec3(0.3, 0.05 + i / 300.0, 1.1 - i / 70.0));
  }

  TrialStage cloud;
  cloud.id = "3";
  cloud.time_s = 2.5;  // equal times are allowed: only going back in time is an error
  cloud.poses = {held_at(0.05, 0.0, 1.0), held_at(0.3, 0.0, 1.0)};
  for (int i = 0; i < 5; ++i) cloud.observed.cloud_m.push_back(Vec3(i / 13.0, -i / 17.0, 0.9));

  t.stages = {hold, release, cloud};
  return t;
}

void check_same_points(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    INFO("point " << i);
    for (int k = 0; k < 3; ++k) {
      if (std::isnan(a[i][k])) {
        CHECK(std::isnan(b[i][k]));
      } else {
        CHECK(a[i][k] == b[i][k]);
      }
    }
  }
}

TEST_CASE("a trial written to a directory reads back as it was", "[twin][trial]") {
  TempDir tmp;
  const Trial written = small_trial();
  const std::string dir = (tmp / "trial").string();  // does not exist yet: write_trial creates it
  write_trial(written, dir);
  CHECK(fs::exists(tmp / "trial" / "first.xyz"));
  CHECK(fs::exists(tmp / "trial" / "2.xyz"));
  CHECK(fs::exists(tmp / "trial" / "3_cloud.xyz"));

  const Trial t = read_trial(dir);
  CHECK(t.directory == dir);
  CHECK(t.material_name == "composite");
  CHECK(t.sheet.is_rectangle());
  CHECK(t.sheet.width_m == 0.4);
  CHECK(t.sheet.height_m == 0.3);
  CHECK(t.thickness_m == 0.0003);
  CHECK(t.mass_kg == 0.036);
  CHECK(t.surface_density_kg_m2 == 0.3);
  CHECK(t.density_kg_m2(0.12) == 0.3);
  CHECK(t.marker_grid_rows == 3);
  CHECK(t.marker_grid_cols == 4);
  REQUIRE(t.marker_uv_m.size() == 12);
  for (std::size_t i = 0; i < 12; ++i) {
    CHECK((t.marker_uv_m[i] - written.marker_uv_m[i]).norm() < 1e-15);
  }
  // Row-major numbering: marker r * cols + c is at origin + (c du, r dv).
  CHECK(t.marker_uv_m[6].isApprox(Vec2(0.25, 0.15)));
  REQUIRE(t.clamps.size() == 2);
  CHECK(t.clamps[0].id == "A");
  CHECK(t.clamps[0].material_point_m == Vec2(0.02, 0.28));
  CHECK(t.clamps[0].grip_radius_m == 0.01);
  CHECK(t.clamps[1].grip_radius_m == 0.0);

  REQUIRE(t.stages.size() == 3);
  for (std::size_t s = 0; s < 3; ++s) {
    INFO("stage " << s);
    const TrialStage& a = written.stages[s];
    const TrialStage& b = t.stages[s];
    CHECK(b.id == a.id);
    CHECK(b.time_s == a.time_s);
    REQUIRE(b.poses.size() == 2);
    for (int c = 0; c < 2; ++c) {
      CHECK(b.poses[c].engaged == a.poses[c].engaged);
      if (a.poses[c].engaged) CHECK(b.poses[c].position_m == a.poses[c].position_m);
      CHECK(b.poses[c].rotation.isIdentity(0.0));
    }
    check_same_points(a.observed.markers_m, b.observed.markers_m);
    check_same_points(a.observed.cloud_m, b.observed.cloud_m);
  }
  CHECK(t.stages[0].markers_file == "first.xyz");
  CHECK(t.stages[1].markers_file == "2.xyz");
  CHECK(t.stages[2].cloud_file == "3_cloud.xyz");
  CHECK(t.stages[0].observed.seen_marker_count() == 10);
  CHECK(t.stages[1].observed.seen_marker_count() == 12);
  CHECK_FALSE(t.stages[2].observed.has_markers());
  CHECK(t.stages[2].observed.seen_marker_count() == 0);

  // Written again from what was read, the observations are the same bytes (the grid's spacing
  // is derived from the markers, so trial.json may differ in the last digit).
  write_trial(t, (tmp / "again").string());
  CHECK(read_text(tmp / "trial" / "first.xyz") == read_text(tmp / "again" / "first.xyz"));
  CHECK(read_text(tmp / "trial" / "first.xyz").find("nan nan nan") != std::string::npos);
  const Trial again = read_trial((tmp / "again").string());
  CHECK(again.stages[0].observed.seen_marker_count() == 10);
}

TEST_CASE("a trial on a mesh sheet, with listed markers, a PLY cloud and a raw scan", "[twin][trial]") {
  TempDir tmp;
  // An L-shaped sheet: the 0.4 x 0.3 rectangle without the triangles of its upper right part.
  const SheetMesh rectangle = make_rectangular_sheet(0.4, 0.3, 0.05);
  SurfaceMesh specimen;
  for (const Vec2& uv : rectangle.rest_uv) specimen.positions.push_back(Vec3(uv.x(), uv.y(), 0.0));
  for (int f = 0; f < rectangle.triangle_count(); ++f) {
    const auto& tri = rectangle.triangles[f];
    const Vec2 centre = (rectangle.rest_uv[tri[0]] + rectangle.rest_uv[tri[1]] + rectangle.rest_uv[tri[2]]) / 3.0;
    if (!(centre.x() > 0.2 && centre.y() > 0.15)) specimen.triangles.push_back(tri);
  }
  // Unused vertices would not make a valid sheet: keep only the ones the triangles use.
  SurfaceMesh compact;
  std::vector<int> index(specimen.positions.size(), -1);
  for (auto& tri : specimen.triangles) {
    std::array<int, 3> renumbered{};
    for (int k = 0; k < 3; ++k) {
      if (index[tri[k]] < 0) {
        index[tri[k]] = static_cast<int>(compact.positions.size());
        compact.positions.push_back(specimen.positions[tri[k]]);
      }
      renumbered[k] = index[tri[k]];
    }
    compact.triangles.push_back(renumbered);
  }
  write_obj(tmp / "specimen.obj", compact);
  const double area_m2 = sheet_mesh_from_flat(compact).total_rest_area();

  Trial t;
  t.material_name = "felt";
  t.sheet.mesh_file = (tmp / "specimen.obj").string();
  t.thickness_m = 0.003;
  t.mass_kg = 0.178 * area_m2;
  t.marker_uv_m = {Vec2(0.1, 0.1), Vec2(0.3, 0.05), Vec2(0.1, 0.25)};
  t.clamps = {{"A", Vec2(0.05, 0.29), 0.0}, {"B", Vec2(0.35, 0.1), 0.0}};
  TrialStage stage;
  stage.id = "scan-1";
  stage.poses = {held_at(0.0, 0.0, 1.0), held_at(0.3, 0.0, 0.9)};
  stage.cloud_file = "scan-1_cloud.ply";
  stage.scan_file = "raw.xyz";
  stage.observed.cloud_m = {Vec3(0.1, 0.0, 0.8), Vec3(0.2, 0.01, 0.7), Vec3(0.25, -0.02, 0.75)};
  t.stages = {stage};
  write_text(tmp / "raw.xyz", "# raw scanner points, not read\n0 0 0\n");
  write_trial(t, tmp.str());

  const Trial back = read_trial(tmp.str());
  CHECK(fs::path(back.sheet.mesh_file).is_absolute());
  CHECK(fs::equivalent(back.sheet.mesh_file, tmp / "specimen.obj"));
  CHECK(read_json(tmp / "trial.json")["sheet"]["mesh_file"] == "specimen.obj");  // relative inside
  CHECK(back.density_kg_m2(area_m2) == Approx(0.178));
  CHECK_FALSE(back.surface_density_kg_m2.has_value());
  CHECK_FALSE(back.marker_grid_rows.has_value());
  REQUIRE(back.marker_uv_m.size() == 3);
  CHECK(back.marker_uv_m[1] == Vec2(0.3, 0.05));
  CHECK(back.stages[0].scan_file == "raw.xyz");
  check_same_points(back.stages[0].observed.cloud_m, stage.observed.cloud_m);
  CHECK(trial_sheet_mesh(back, 1000).triangle_count() == static_cast<int>(compact.triangles.size()));

  // The cut-out corner is not sheet: a marker there is off it, though inside the bounding box.
  json j = read_json(tmp / "trial.json");
  j["markers"]["list_m"][2] = json::array({0.35, 0.25});
  write_json(tmp / "trial.json", j);
  CHECK_THROWS_WITH(read_trial(tmp.str()),
                    Catch::Contains("trial.json") && Catch::Contains("'markers.list_m[2]'") &&
                        Catch::Contains("marker 2 at (0.35, 0.25) m") && Catch::Contains("not on the sheet"));
}

TEST_CASE("xyz files: comments, blank lines, CRLF and NaN markers", "[twin][trial]") {
  TempDir tmp;
  const fs::path path = tmp / "points.xyz";
  write_text(path, "# x y z (m)\r\n\r\n 1 2.5 -3e-2\r\n  # indented comment\n+0.5 0 1\nnan NaN nan\n");
  const std::vector<Vec3> points = read_xyz_file(path.string(), true);
  REQUIRE(points.size() == 3);
  CHECK(points[0] == Vec3(1.0, 2.5, -0.03));
  CHECK(points[1] == Vec3(0.5, 0.0, 1.0));
  CHECK(points[2].array().isNaN().all());
  CHECK_THROWS_WITH(read_xyz_file(path.string(), false),
                    Catch::Contains("points.xyz:6:") && Catch::Contains("expected a finite number"));

  write_xyz_file(path.string(), {Vec3(0.1, 1.0 / 3.0, -2.0), Vec3(kNaN, kNaN, kNaN)});
  const std::vector<Vec3> back = read_xyz_file(path.string(), true);
  REQUIRE(back.size() == 2);
  CHECK(back[0] == Vec3(0.1, 1.0 / 3.0, -2.0));
  CHECK(back[1].array().isNaN().all());
  CHECK_THROWS_WITH(write_xyz_file(path.string(), {Vec3(0.0, kNaN, 1.0)}),
                    Catch::Contains("points.xyz") && Catch::Contains("point 0"));
  CHECK_FALSE(fs::exists(tmp / "points.xyz.tmp"));
}

TEST_CASE("write_trial refuses a trial it could not read back, writing nothing", "[twin][trial]") {
  TempDir tmp;
  Trial off_grid = small_trial();
  off_grid.marker_uv_m[7].x() += 0.01;
  CHECK_THROWS_WITH(write_trial(off_grid, (tmp / "a").string()),
                    Catch::Contains("marker 7") && Catch::Contains("3 x 4 grid"));
  Trial short_stage = small_trial();
  short_stage.stages[1].observed.markers_m.pop_back();
  CHECK_THROWS_WITH(write_trial(short_stage, (tmp / "b").string()),
                    Catch::Contains("stage '2' has 11 marker positions for 12 markers"));
  Trial unobserved = small_trial();
  unobserved.stages[2].observed.cloud_m.clear();
  CHECK_THROWS_WITH(write_trial(unobserved, (tmp / "c").string()), Catch::Contains("stage '3'"));
  CHECK_FALSE(fs::exists(tmp / "a"));
  CHECK_FALSE(fs::exists(tmp / "b"));
  CHECK_FALSE(fs::exists(tmp / "c"));

  // A single column: its spacing along u is free, and the markers still read back.
  Trial column = small_trial();
  column.marker_grid_rows = 12;
  column.marker_grid_cols = 1;
  for (int r = 0; r < 12; ++r) column.marker_uv_m[r] = Vec2(0.2, 0.01 + r * 0.025);
  write_trial(column, (tmp / "d").string());
  const Trial back = read_trial((tmp / "d").string());
  REQUIRE(back.marker_uv_m.size() == 12);
  CHECK(back.marker_grid_cols == 1);
  CHECK(back.marker_uv_m[11].isApprox(Vec2(0.2, 0.285)));
}

// A good trial written into a fresh folder of `tmp`, to be broken by one test.
std::string good_trial(const TempDir& tmp, const std::string& name) {
  const std::string dir = (tmp / name).string();
  write_trial(small_trial(), dir);
  return dir;
}

TEST_CASE("broken trial directories are rejected naming the file and the field or line", "[twin][trial]") {
  TempDir tmp;
  const std::string dir = good_trial(tmp, "t");

  SECTION("missing trial.json") {
    CHECK_THROWS_WITH(read_trial((tmp / "nowhere").string()),
                      Catch::Contains("nowhere/trial.json") && Catch::Contains("cannot open"));
  }
  SECTION("missing markers file") {
    fs::remove(fs::path(dir) / "first.xyz");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("trial.json") &&
                                           Catch::Contains("'stages[0].markers_file'") &&
                                           Catch::Contains("first.xyz") && Catch::Contains("does not exist"));
  }
  SECTION("non-numeric value in an xyz file") {
    write_text(fs::path(dir) / "2.xyz", "0 0 1\n0 0 1\n0.1 abc 1\n");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("2.xyz:3: ") &&
                                           Catch::Contains("expected a number") && Catch::Contains("'abc'"));
  }
  SECTION("wrong number of values on a line") {
    write_text(fs::path(dir) / "2.xyz", "# header\n0 0 1\n0 0\n");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("2.xyz:3: ") && Catch::Contains("expected 3 values"));
  }
  SECTION("infinite value") {
    write_text(fs::path(dir) / "first.xyz", "0 0 1\n0 -inf 1\n");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("first.xyz:2: ") &&
                                           Catch::Contains("expected a finite number") && Catch::Contains("'-inf'"));
  }
  SECTION("partly NaN marker") {
    write_text(fs::path(dir) / "first.xyz", "nan nan nan\n\nnan 0.2 1\n");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("first.xyz:3: ") && Catch::Contains("\"nan nan nan\""));
  }
  SECTION("NaN in a cloud") {
    write_text(fs::path(dir) / "3_cloud.xyz", "0 0 1\nnan nan nan\n");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("3_cloud.xyz:2: ") &&
                                           Catch::Contains("expected a finite number"));
  }
  SECTION("marker count differs from the manifest") {
    std::string lines;
    for (int i = 0; i < 11; ++i) lines += "0 0 1\n";
    write_text(fs::path(dir) / "2.xyz", lines);
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("'stages[1].markers_file'") &&
                                           Catch::Contains("2.xyz") && Catch::Contains("11 marker lines") &&
                                           Catch::Contains("expected 12"));
  }

  // The remaining cases edit trial.json.
  const fs::path manifest = fs::path(dir) / "trial.json";
  const json good = read_json(manifest);
  auto rejects = [&](const json& broken, const std::string& field, const std::string& what) {
    write_json(manifest, broken);
    CHECK_THROWS_WITH(read_trial(dir),
                      Catch::Contains("trial.json") && Catch::Contains(field) && Catch::Contains(what));
  };

  SECTION("unknown clamp id in a stage") {
    json j = good;
    j["stages"][1]["clamps"]["Z"] = json::array({0.1, 0.1, 1.0});
    rejects(j, "'stages[1].clamps.Z'", "names no clamp");
  }
  SECTION("a stage that omits a clamp") {
    json j = good;
    j["stages"][1]["clamps"].erase("A");
    rejects(j, "'stages[1].clamps.A'", "is missing");
  }
  SECTION("a stage with every clamp released") {
    json j = good;
    j["stages"][2]["clamps"]["A"] = "released";
    j["stages"][2]["clamps"]["B"] = "released";
    rejects(j, "'stages[2].clamps'", "no clamp holding");
  }
  SECTION("clamps farther apart in the world than on the sheet") {
    json j = good;
    j["stages"][0]["clamps"]["B"] = json::array({0.5, 0.0, 1.0});
    rejects(j, "'stages[0].clamps'", "clamps 'A' and 'B' 0.5000 m apart in the world, but they are 0.3600 m apart");
  }
  SECTION("clamps a little farther apart than on the sheet are within measurement error") {
    json j = good;
    j["stages"][0]["clamps"]["B"] = json::array({0.36 * 1.02 + 0.004, 0.0, 1.0});
    write_json(manifest, j);
    CHECK_NOTHROW(read_trial(dir));
  }
  SECTION("density that disagrees with mass / area (the felt sheet)") {
    json j = good;
    j["sheet"] = {{"width_m", 0.615}, {"height_m", 0.612}};
    j["mass_kg"] = 0.0669;
    j["surface_density_kg_m2"] = 0.0018;
    rejects(j, "'surface_density_kg_m2'", "is 0.0018 kg/m^2, but mass_kg 0.0669 kg");
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("implies 0.178 kg/m^2"));
  }
  SECTION("neither mass nor density") {
    json j = good;
    j.erase("mass_kg");
    j.erase("surface_density_kg_m2");
    rejects(j, "'mass_kg' or 'surface_density_kg_m2'", "must be given");
  }
  SECTION("marker off the sheet") {
    json j = good;
    j["markers"]["grid"]["origin_m"] = json::array({0.2, 0.05});
    rejects(j, "'markers.grid'", "marker 3 at (0.5, 0.05) m, which is not on the sheet");
  }
  SECTION("clamp off the sheet") {
    json j = good;
    j["clamps"][1]["material_point_m"] = json::array({0.38, 0.31});
    rejects(j, "'clamps[1].material_point_m'", "not on the sheet");
  }
  SECTION("duplicate clamp id") {
    json j = good;
    j["clamps"][1]["id"] = "A";
    rejects(j, "'clamps[1].id'", "used by an earlier clamp");
  }
  SECTION("duplicate stage id") {
    json j = good;
    j["stages"][2]["id"] = "1";
    rejects(j, "'stages[2].id'", "used by an earlier stage");
  }
  SECTION("unknown field") {
    json j = good;
    j["thicknes_m"] = 0.0003;
    rejects(j, "'thicknes_m'", "is not a known field");
  }
  SECTION("non-positive thickness") {
    json j = good;
    j["thickness_m"] = 0.0;
    rejects(j, "'thickness_m'", "must be a positive number");
  }
  SECTION("time going back") {
    json j = good;
    j["stages"][2]["time_s"] = 1.0;
    rejects(j, "'stages[2].time_s'", "earlier than");
  }
  SECTION("both markers and cloud in a stage") {
    json j = good;
    j["stages"][2]["markers_file"] = "2.xyz";
    rejects(j, "'stages[2].markers_file' or 'cloud_file'", "exactly one");
  }
  SECTION("missing scan file") {
    json j = good;
    j["stages"][0]["scan_file"] = "raw_1.xyz";
    rejects(j, "'stages[0].scan_file'", "raw_1.xyz");
  }
}

}  // namespace
}  // namespace twin::trial_test
