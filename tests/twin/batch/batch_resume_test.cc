// What `twin batch` reads back from an earlier run (twin/batch/batch_resume.h): a done.json of the
// same entry is the material's row; one of another entry is redone; a corrupt one is reported
// naming the file and what was expected, left in place, and never silently diagnosed again.
// No diagnosis runs here: the trial directories are empty, and would fail if one did.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "tests/support/temp_dir.h"
#include "twin/base/atomic_file.h"
#include "twin/batch/batch_resume.h"
#include "twin/batch/batch_runner.h"

namespace {

namespace fs = std::filesystem;

twin::batch::BatchManifest one_material(const testing_support::TempDir& dir) {
  fs::create_directories(dir / "t");
  return twin::batch::batch_manifest_from_json(
      nlohmann::json::parse(R"({"materials": [{"name": "lot7", "train": ["t"], "test": ["t"]}]})"), "manifest.json",
      dir.str());
}

// A done.json as the batch writes it for `material`, with `row` changed by `edit`.
void write_done(const fs::path& dir, const twin::batch::BatchMaterial& material,
                const std::function<void(nlohmann::json&)>& edit = {}) {
  twin::batch::BatchRow row;
  row.name = material.name;
  row.status = "done";
  row.verdict = "none";
  row.held_out_before_mm = 0.5;
  nlohmann::json record = {{"fingerprint", material.fingerprint}, {"row", twin::batch::row_json(row)}};
  if (edit) edit(record);
  fs::create_directories(dir);
  testing_support::write_file(dir / "done.json", record.dump(2));
}

std::string error_of(const fs::path& dir, const twin::batch::BatchMaterial& material) {
  try {
    (void)twin::batch::finished_row(dir, material);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a done.json of the same entry is read back, one of another entry is redone", "[batch]") {
  testing_support::TempDir dir("batch_resume_ok");
  const twin::batch::BatchManifest manifest = one_material(dir);
  const twin::batch::BatchMaterial& material = manifest.materials[0];
  const fs::path out = dir / "out" / "lot7";
  CHECK_FALSE(twin::batch::finished_row(out, material));  // never run
  write_done(out, material);
  testing_support::write_file(out / "material.json", "{}");
  const std::optional<twin::batch::BatchRow> row = twin::batch::finished_row(out, material);
  REQUIRE(row);
  CHECK(row->status == "already done");
  CHECK(row->held_out_before_mm == 0.5);
  write_done(out, material, [](nlohmann::json& j) { j["fingerprint"] = "another entry"; });
  CHECK_FALSE(twin::batch::finished_row(out, material));
}

TEST_CASE("a corrupt done.json is reported naming the file and what was expected", "[batch]") {
  testing_support::TempDir dir("batch_resume_corrupt");
  const twin::batch::BatchManifest manifest = one_material(dir);
  const twin::batch::BatchMaterial& material = manifest.materials[0];
  const fs::path out = dir / "out" / "lot7";
  const std::string file = (out / "done.json").string();
  write_done(out, material);
  testing_support::write_file(out / "material.json", "{}");

  SECTION("not JSON (cut short)") {
    testing_support::write_file(out / "done.json", "{\"fingerprint\": \"");
    CHECK_THAT(error_of(out, material), Catch::Contains(file) && Catch::Contains("not valid JSON") &&
                                            Catch::Contains("corrupt batch resume file") &&
                                            Catch::Contains("\"fingerprint\""));
  }
  SECTION("a field missing") {
    write_done(out, material, [](nlohmann::json& j) { j["row"].erase("verdict"); });
    CHECK_THAT(error_of(out, material), Catch::Contains(file) && Catch::Contains("'row.verdict' is missing"));
  }
  SECTION("a field of another type") {
    write_done(out, material, [](nlohmann::json& j) { j["row"]["seconds"] = "soon"; });
    CHECK_THAT(error_of(out, material), Catch::Contains(file) && Catch::Contains("'row.seconds' must be a number"));
  }
  SECTION("another material's record") {
    write_done(out, material, [](nlohmann::json& j) { j["row"]["name"] = "lot8"; });
    CHECK_THAT(error_of(out, material), Catch::Contains(file) && Catch::Contains("'row.name'"));
  }
  SECTION("its material.json gone") {
    fs::remove(out / "material.json");
    CHECK_THAT(error_of(out, material), Catch::Contains(file) && Catch::Contains((out / "material.json").string()));
  }
}

TEST_CASE("twin batch reports a corrupt done.json as the material's failure and leaves it as it was", "[batch]") {
  testing_support::TempDir dir("batch_resume_run");
  const twin::batch::BatchManifest manifest = one_material(dir);
  const fs::path out = dir / "out";
  fs::create_directories(out / "lot7");
  testing_support::write_file(out / "lot7" / "material.json", "{}");
  testing_support::write_file(out / "lot7" / "done.json", "garbage");
  twin::batch::BatchOptions options;
  options.out = out.string();
  const twin::batch::BatchResult result = twin::batch::run_batch(manifest, options);
  REQUIRE(result.rows.size() == 1);
  CHECK(result.failed == 1);
  CHECK(result.rows[0].status == "failed");
  CHECK_THAT(result.rows[0].error,
             Catch::Contains((out / "lot7" / "done.json").string()) && Catch::Contains("corrupt batch resume file"));
  std::ifstream in(out / "lot7" / "done.json");
  CHECK(std::string(std::istreambuf_iterator<char>(in), {}) == "garbage");
  CHECK(fs::exists(out / "lot7" / "material.json"));
  CHECK_FALSE(fs::exists(out / "lot7" / "running.json"));  // not diagnosed
}

TEST_CASE("an unreadable running.json is named in the note", "[batch]") {
  testing_support::TempDir dir("batch_resume_running");
  CHECK(twin::batch::interrupted_run(dir / "x").empty());
  testing_support::write_file(dir / "running.json", R"({"rank": "zero", "pid": 1, "host": "h", "started": "s"})");
  CHECK_THAT(twin::batch::interrupted_run(dir.str()),
             Catch::Contains((dir / "running.json").string()) && Catch::Contains("'rank' must be an integer"));
}
