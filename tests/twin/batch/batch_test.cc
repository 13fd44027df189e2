// `twin batch` (issue 38, item 1): a manifest of materials diagnosed one after another, each
// into its own directory with its material file and report; a summary table; a failing material
// recorded without stopping the others; a second run redoing nothing finished, and a changed
// entry or an interrupted one redone. The trials come from the scanner lab with the twin's own
// model on a coarse mesh (tests/support/uniform_lab_config.h): these check the batch's
// mechanics, not the diagnosis's accuracy.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "sim_hw/scanner_lab.h"
#include "tests/support/temp_dir.h"
#include "tests/support/uniform_lab_config.h"
#include "twin/batch/batch_runner.h"
#include "twin/model/material.h"

namespace {

namespace fs = std::filesystem;
constexpr int kTriangles = 150;

void write_trial(const fs::path& dir, std::uint64_t seed) {
  const sim_hw::ScannerLabConfig config = testing_support::uniform_lab_config(seed, kTriangles);
  const sim_hw::LabTrial lab = sim_hw::make_lab_trial(config);
  sim_hw::write_lab_trial(lab, config, dir.string(), dir.string() + "_truth");
}

// Two materials with their trials, and a third whose training trial is broken (not a trial).
nlohmann::json manifest_in(const testing_support::TempDir& dir) {
  write_trial(dir / "trials" / "a_train", 3);
  write_trial(dir / "trials" / "a_test", 4);
  write_trial(dir / "trials" / "b_train", 5);
  fs::create_directories(dir / "trials" / "broken");
  std::ofstream(dir / "trials" / "broken" / "trial.json") << "{\"not\": \"a trial\"}";
  return nlohmann::json::parse(R"({
    "materials": [
      {"name": "lot_a", "train": ["trials/a_train"], "test": ["trials/a_test"]},
      {"name": "lot_broken", "train": ["trials/broken"], "test": ["trials/a_test"]},
      {"name": "lot_b", "train": ["trials/b_train"], "test": ["trials/a_test"]}
    ],
    "diagnose": {"triangles": 150, "path_triangles": 0, "refits": 1, "effects": "orthotropic_stiffness",
                 "noise_mm": 0.3, "discretisation_check": false}
  })");
}

std::string error_of(const nlohmann::json& j, const std::string& base) {
  try {
    (void)twin::batch::batch_manifest_from_json(j, "manifest.json", base);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a batch diagnoses every material, records a failure, and a rerun redoes only what is not finished",
          "[batch]") {
  testing_support::TempDir dir("batch_run");
  nlohmann::json j = manifest_in(dir);
  const fs::path out = dir / "out";
  twin::batch::BatchOptions options;
  options.out = out.string();

  const twin::batch::BatchResult first =
      twin::batch::run_batch(twin::batch::batch_manifest_from_json(j, "manifest.json", dir.str()), options);
  REQUIRE(first.rows.size() == 3);
  CHECK(first.done == 2);
  CHECK(first.failed == 1);
  CHECK(first.rows[0].name == "lot_a");
  CHECK(first.rows[0].status == "done");
  CHECK(first.rows[1].status == "failed");
  CHECK_THAT(first.rows[1].error, Catch::Contains("broken"));
  CHECK(first.rows[2].status == "done");
  for (const char* name : {"lot_a", "lot_b"}) {
    INFO(name);
    CHECK(fs::exists(out / name / "done.json"));
    CHECK(fs::exists(out / name / "verdict.json"));
    CHECK(fs::exists(out / name / "report.md"));
    // The characterised material is a file the twin reads.
    const twin::Material m = twin::read_material_file((out / name / "material.json").string());
    CHECK(m.bending_rigidity_u_Nm > 0.0);
  }
  CHECK(first.rows[0].held_out_before_mm > 0.0);
  CHECK(first.rows[0].noise_sigma_mm == Approx(0.3));
  CHECK(fs::exists(out / "lot_broken" / "failed.json"));
  CHECK_FALSE(fs::exists(out / "lot_broken" / "done.json"));
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  REQUIRE(summary["materials"].size() == 3);
  CHECK(summary["materials"][1]["status"] == "failed");
  std::ifstream table(out / "summary.md");
  const std::string text((std::istreambuf_iterator<char>(table)), std::istreambuf_iterator<char>());
  CHECK_THAT(text, Catch::Contains("| lot_a | done |") && Catch::Contains("| lot_broken | failed |"));

  // Again: the finished materials are read back, not redone; the failed one is tried again.
  // lot_b looks interrupted (its done.json gone and its running.json left, as if killed before
  // writing it); lot_a's verdict file is kept as it was.
  fs::remove(out / "lot_b" / "done.json");
  std::ofstream(out / "lot_b" / "running.json")
      << R"({"rank": 2, "pid": 4242, "host": "cellpc", "started": "2026-12-01T08:00:00Z"})";
  const auto lot_a_written = fs::last_write_time(out / "lot_a" / "verdict.json");
  const twin::batch::BatchResult second =
      twin::batch::run_batch(twin::batch::batch_manifest_from_json(j, "manifest.json", dir.str()), options);
  REQUIRE(second.rows.size() == 3);
  CHECK(second.already_done == 1);
  CHECK(second.done == 1);
  CHECK(second.failed == 1);
  CHECK(second.rows[0].status == "already done");
  CHECK(second.rows[0].verdict == first.rows[0].verdict);
  CHECK(second.rows[0].held_out_before_mm == first.rows[0].held_out_before_mm);
  CHECK(second.rows[2].status == "done");
  CHECK_THAT(second.rows[2].note, Catch::Contains("earlier run stopped") && Catch::Contains("rank 2, pid 4242 on cellpc"));
  CHECK(second.rows[0].note.empty());
  CHECK_FALSE(fs::exists(out / "lot_b" / "running.json"));
  CHECK(second.rows[2].verdict == first.rows[2].verdict);  // the same diagnosis, run again
  CHECK(second.rows[2].held_out_before_mm == Approx(first.rows[2].held_out_before_mm).epsilon(1e-9));
  CHECK(fs::last_write_time(out / "lot_a" / "verdict.json") == lot_a_written);

  // A changed entry (another test trial) is redone.
  j["materials"][0]["test"] = {"trials/a_train"};
  const twin::batch::BatchResult third =
      twin::batch::run_batch(twin::batch::batch_manifest_from_json(j, "manifest.json", dir.str()), options);
  CHECK(third.rows[0].status == "done");
  CHECK(third.rows[2].status == "already done");
}

TEST_CASE("manifest errors name the file and the field", "[batch]") {
  testing_support::TempDir dir("batch_manifest");
  fs::create_directories(dir / "t");
  const std::string base = dir.str();
  auto with = [&](const char* text) { return error_of(nlohmann::json::parse(text), base); };
  CHECK(with(R"({"materials": [{"name": "a", "train": ["t"], "test": ["t"]}]})").empty());
  CHECK_THAT(with(R"({"materials": []})"), Catch::Contains("manifest.json") && Catch::Contains("'materials'"));
  CHECK_THAT(with(R"({"materials": [{"name": "a/b", "train": ["t"], "test": ["t"]}]})"),
             Catch::Contains("'materials[0].name'") && Catch::Contains("letters"));
  CHECK_THAT(with(R"({"materials": [{"name": "a", "train": ["t"], "test": ["t"]},
                                    {"name": "a", "train": ["t"], "test": ["t"]}]})"),
             Catch::Contains("'materials[1].name'") && Catch::Contains("repeats"));
  CHECK_THAT(with(R"({"materials": [{"name": "a", "train": ["missing"], "test": ["t"]}]})"),
             Catch::Contains("'materials[0].train[0]'") && Catch::Contains("missing"));
  CHECK_THAT(with(R"({"materials": [{"name": "a", "train": [], "test": ["t"]}]})"),
             Catch::Contains("'materials[0].train'"));
  CHECK_THAT(with(R"({"materials": [{"name": "a", "train": ["t"], "test": ["t"]}], "diagnose": {"refits": 0}})"),
             Catch::Contains("'diagnose.refits'"));
  CHECK_THAT(with(R"({"materials": [{"name": "a", "train": ["t"], "test": ["t"]}], "diagnose": {"optimiser": "lm"}})"),
             Catch::Contains("'diagnose.optimiser'"));
  CHECK_THAT(with(R"({"materials": [{"name": "a", "train": ["t"], "test": ["t"], "material": "none.json"}]})"),
             Catch::Contains("'materials[0].material'"));
}
