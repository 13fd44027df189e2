// Stage load ages (stage_age.h): the optional "clamps_moved_at_s" of a trial stage, its
// defaults, reading and writing it, and bad values named with file and field.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/support/temp_dir.h"
#include "twin/trials/stage_age.h"

namespace twin {
namespace {

namespace fs = std::filesystem;

ClampPose held_at(double x, double z) {
  ClampPose p;
  p.position_m = Vec3(x, 0.0, z);
  return p;
}

TrialStage stage(const std::string& id, std::optional<double> time_s, std::vector<ClampPose> poses) {
  TrialStage s;
  s.id = id;
  s.time_s = time_s;
  s.poses = std::move(poses);
  for (int i = 0; i < 4; ++i) s.observed.markers_m.push_back(Vec3(0.1 * i, 0.0, 0.9));
  return s;
}

// A 0.4 x 0.3 m sheet, two clamps at its top corners, 2 x 2 markers, stages at given times.
Trial timed_trial() {
  Trial t;
  t.material_name = "composite";
  t.sheet.width_m = 0.4;
  t.sheet.height_m = 0.3;
  t.thickness_m = 0.0003;
  t.surface_density_kg_m2 = 0.3;
  t.marker_grid_rows = 2;
  t.marker_grid_cols = 2;
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) t.marker_uv_m.push_back(Vec2(0.1 + c * 0.2, 0.1 + r * 0.1));
  }
  t.clamps = {{"A", Vec2(0.02, 0.28), 0.01}, {"B", Vec2(0.38, 0.28), 0.01}};
  t.stages = {stage("1", 50.0, {held_at(0.0, 1.0), held_at(0.36, 1.0)}),
              stage("2", 400.0, {held_at(0.0, 1.0), held_at(0.3, 1.2)}),
              stage("3", 700.0, {held_at(0.0, 1.0), held_at(0.3, 1.2)}),
              stage("4", 1000.0, {held_at(0.0, 1.1), held_at(0.3, 1.2)})};
  t.stages[0].clamps_moved_at_s = 10.0;
  t.stages[1].clamps_moved_at_s = 380.0;
  return t;
}

TEST_CASE("stage ages: given, defaulted from the previous scan, kept while nothing moves", "[twin][trial_effects]") {
  Trial t = timed_trial();
  std::vector<double> ages = stage_load_ages_s(t.stages);
  REQUIRE(ages.size() == 4);
  CHECK(ages[0] == 40.0);   // given
  CHECK(ages[1] == 20.0);   // given
  CHECK(ages[2] == 320.0);  // same poses as stage 2: still relaxing since 380 s
  CHECK(ages[3] == 300.0);  // moved after stage 3's scan at 700 s
  // Without the field: stage 1 unknown; later ones since the previous scan.
  for (TrialStage& s : t.stages) s.clamps_moved_at_s.reset();
  ages = stage_load_ages_s(t.stages);
  CHECK(std::isnan(ages[0]));
  CHECK(ages[1] == 350.0);
  CHECK(ages[2] == 650.0);  // nothing moved since stage 2's clamps (after the scan at 50 s)
  CHECK(ages[3] == 300.0);
  // Without times nothing is known.
  for (TrialStage& s : t.stages) s.time_s.reset();
  for (double a : stage_load_ages_s(t.stages)) CHECK(std::isnan(a));
}

TEST_CASE("clamps_moved_at_s is written, read back, and checked naming file and field", "[twin][trial_effects]") {
  testing_support::TempDir tmp("twin_stage_age_test");
  const std::string dir = (tmp / "t").string();
  write_trial(timed_trial(), dir);
  const Trial back = read_trial(dir);
  REQUIRE(back.stages.size() == 4);
  CHECK(back.stages[0].clamps_moved_at_s == 10.0);
  CHECK(back.stages[1].clamps_moved_at_s == 380.0);
  CHECK_FALSE(back.stages[2].clamps_moved_at_s.has_value());
  CHECK(stage_load_ages_s(back.stages) == stage_load_ages_s(timed_trial().stages));

  std::ifstream in(fs::path(dir) / "trial.json");
  const nlohmann::json good = nlohmann::json::parse(in);
  const auto rejects = [&](const nlohmann::json& j, const std::string& field, const std::string& what) {
    testing_support::write_file(fs::path(dir) / "trial.json", j.dump(2));
    CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("trial.json") && Catch::Contains(field) &&
                                           Catch::Contains(what));
  };
  SECTION("not a number") {
    nlohmann::json j = good;
    j["stages"][1]["clamps_moved_at_s"] = "soon";
    rejects(j, "'stages[1].clamps_moved_at_s'", "number");
  }
  SECTION("after the scan") {
    nlohmann::json j = good;
    j["stages"][1]["clamps_moved_at_s"] = 401.0;
    rejects(j, "'stages[1].clamps_moved_at_s'", "later than the stage's time_s");
  }
  SECTION("before the previous scan") {
    nlohmann::json j = good;
    j["stages"][1]["clamps_moved_at_s"] = 40.0;
    rejects(j, "'stages[1].clamps_moved_at_s'", "earlier than the 50 s");
  }
  SECTION("without a time") {
    nlohmann::json j = good;
    j["stages"][0].erase("time_s");
    rejects(j, "'stages[0].clamps_moved_at_s'", "needs the stage's 'time_s'");
  }
  SECTION("the writer refuses what the reader would") {
    Trial t = timed_trial();
    t.stages[2].clamps_moved_at_s = 800.0;
    CHECK_THROWS_WITH(write_trial(t, (tmp / "u").string()), Catch::Contains("stage '3'") &&
                                                                  Catch::Contains("clamps_moved_at_s"));
  }
}

TEST_CASE("a repeated scan of one pose keeps the moment its clamps stopped", "[twin][trial_effects]") {
  testing_support::TempDir tmp("twin_stage_age_repeat");
  // Stage 3 scans stage 2's pose again 300 s later: the same poses, the same clamps_moved_at_s
  // (before stage 2's scan, which is allowed only for such a repeat).
  Trial t = timed_trial();
  t.stages[2].clamps_moved_at_s = 380.0;
  const std::string dir = (tmp / "t").string();
  write_trial(t, dir);
  const Trial back = read_trial(dir);
  CHECK(back.stages[2].clamps_moved_at_s == 380.0);
  CHECK(stage_load_ages_s(back.stages)[2] == 320.0);
  // The same moment with other poses: the clamps cannot have stopped before the last scan.
  std::ifstream in(fs::path(dir) / "trial.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["stages"][2]["clamps"]["B"][2] = 1.21;
  testing_support::write_file(fs::path(dir) / "trial.json", j.dump(2));
  CHECK_THROWS_WITH(read_trial(dir), Catch::Contains("'stages[2].clamps_moved_at_s'") &&
                                         Catch::Contains("earlier than the 400 s"));
}

}  // namespace
}  // namespace twin
