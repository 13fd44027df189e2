// Issue 38 items 2-5: the real programs under `mpirun -np 3` on this machine (Debian's OpenMPI),
// against the same programs run serially: the rank group's ways of spreading tasks and its
// teams, `twin batch` (the same material files and verdicts as a serial batch), a rank killed
// partway (the run fails, no material looks finished that is not, and the same command again
// redoes what was interrupted and says so), one diagnosis's refit searches over the ranks
// (`twin diagnose`, and `twin batch` in teams), and plan_grasps (the same plan). Three ranks on
// two cores: these check results, not speed.
#include <catch2/catch.hpp>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "sim_hw/scanner_lab.h"
#include "tests/support/child_process.h"
#include "tests/support/run_command.h"
#include "tests/support/temp_dir.h"
#include "tests/support/uniform_lab_config.h"

namespace {

namespace fs = std::filesystem;
constexpr int kTriangles = 150;
const std::vector<std::string> kMaterials = {"lot_a", "lot_b", "lot_c"};

std::vector<std::string> mpirun_args(int ranks) {
  // Three ranks on two cores, unbound; containers often forbid the cross-memory attach that
  // OpenMPI's shared-memory transport tries first.
  std::vector<std::string> args = {"--oversubscribe", "--bind-to", "none", "--mca", "btl_vader_single_copy_mechanism",
                                   "none", "-np", std::to_string(ranks)};
  if (geteuid() == 0) args.push_back("--allow-run-as-root");  // CI runs as root
  return args;
}

std::string mpirun(int ranks) {
  std::string s = MPIEXEC;
  for (const std::string& a : mpirun_args(ranks)) s += " " + a;
  return s;
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  INFO(path.string());
  REQUIRE(in);
  return nlohmann::json::parse(in);
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Materials `names`, each with its own training trial (seeds first_seed, first_seed + 1, ...),
// sharing one held-out trial (test_seed), of the composite or of `truth`; the manifest's path.
fs::path write_batch_inputs(const testing_support::TempDir& dir, const std::vector<std::string>& names,
                            std::uint64_t first_seed, std::uint64_t test_seed,
                            const std::optional<twin::Material>& truth = std::nullopt) {
  auto trial = [&](const std::string& name, std::uint64_t seed) {
    sim_hw::ScannerLabConfig config = testing_support::uniform_lab_config(seed, kTriangles);
    config.material_override = truth;
    const fs::path path = dir / "trials" / name;
    sim_hw::write_lab_trial(sim_hw::make_lab_trial(config), config, path.string(), path.string() + "_truth");
  };
  trial("test", test_seed);
  nlohmann::json materials = nlohmann::json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    trial(names[i], first_seed + i);
    materials.push_back({{"name", names[i]}, {"train", {"trials/" + names[i]}}, {"test", {"trials/test"}}});
  }
  const nlohmann::json manifest = {
      {"materials", materials},
      {"diagnose", {{"triangles", kTriangles}, {"path_triangles", 0}, {"refits", 1},
                    {"effects", "orthotropic_stiffness"}, {"noise_mm", 0.3}, {"discretisation_check", false}}}};
  const fs::path path = dir / "manifest.json";
  std::ofstream(path) << manifest.dump(2);
  return path;
}

std::string batch_args(const fs::path& manifest, const fs::path& out) {
  return std::string(" ") + TWIN_EXE + " --threads 1 batch " + manifest.string() + " --out " + out.string();
}

// The same diagnosis: verdict and effect, held-out errors, the characterised material.
void check_same_material(const fs::path& serial, const fs::path& other, const std::string& name) {
  INFO(name);
  const nlohmann::json a = read_json(serial / name / "done.json")["row"], b = read_json(other / name / "done.json")["row"];
  CHECK(a["verdict"] == b["verdict"]);
  CHECK(a["effect"] == b["effect"]);
  CHECK(b["held_out_before_mm"].get<double>() == Approx(a["held_out_before_mm"].get<double>()).epsilon(1e-9));
  CHECK(b["noise_sigma_mm"].get<double>() == Approx(a["noise_sigma_mm"].get<double>()).epsilon(1e-9));
  CHECK(read_text(serial / name / "material.json") == read_text(other / name / "material.json"));
  CHECK(read_text(serial / name / "verdict.json") == read_text(other / name / "verdict.json"));
}

// Every result file that exists is whole (parses), and a finished material has its material file.
void check_nothing_half_written(const fs::path& out) {
  for (const std::string& name : kMaterials) {
    INFO(name);
    for (const char* file : {"done.json", "failed.json", "running.json", "material.json"}) {
      if (fs::exists(out / name / file)) CHECK_NOTHROW(nlohmann::json::parse(read_text(out / name / file)));
    }
    if (fs::exists(out / name / "done.json")) CHECK(fs::exists(out / name / "material.json"));
  }
}

}  // namespace

TEST_CASE("tasks spread over 3 ranks run once each and their results arrive in order", "[mpi]") {
  std::string output;
  const int status = testing_support::run_command(mpirun(3) + " " + RANK_GROUP_CHECK_EXE, output);
  INFO(output);
  CHECK(status == 0);
  CHECK_THAT(output, Catch::Contains("rank_group_check: 3 ranks") && Catch::Contains(", ok"));
}

TEST_CASE("twin batch over 3 ranks writes what the serial batch writes, and resumes a killed run", "[mpi]") {
  testing_support::TempDir dir("mpi_batch");
  const fs::path manifest = write_batch_inputs(dir, kMaterials, 11, 4);
  const fs::path serial = dir / "serial", spread = dir / "mpi", killed = dir / "killed";

  std::string output;
  REQUIRE(testing_support::run_command(batch_args(manifest, serial), output) == 0);  // serial: no mpirun
  output.clear();
  const int status = testing_support::run_command(mpirun(3) + batch_args(manifest, spread), output);
  INFO(output);
  REQUIRE(status == 0);
  CHECK_THAT(output, Catch::Contains("3 materials over 3 ranks"));
  for (const std::string& name : kMaterials) check_same_material(serial, spread, name);
  const nlohmann::json summary = read_json(spread / "summary.json");
  CHECK(summary["ranks"] == 3);
  REQUIRE(summary["materials"].size() == kMaterials.size());
  for (std::size_t i = 0; i < kMaterials.size(); ++i) CHECK(summary["materials"][i]["name"] == kMaterials[i]);
  // Progress lines say which rank did what, and more than one rank diagnosed.
  int ranks_diagnosing = 0;
  for (int r = 0; r < 3; ++r) ranks_diagnosing += output.find("[rank " + std::to_string(r) + "/3] lot_") != std::string::npos;
  CHECK(ranks_diagnosing >= 2);

  // Again over MPI: nothing redone.
  output.clear();
  REQUIRE(testing_support::run_command(mpirun(3) + batch_args(manifest, spread), output) == 0);
  CHECK_THAT(read_text(spread / "summary.md"), Catch::Contains("0 diagnosed now, 3 already done, 0 failed"));

  // A rank killed while it diagnoses a material: mpirun stops the run and fails.
  std::vector<std::string> args = mpirun_args(3);
  for (const char* a : {TWIN_EXE, "--threads", "1", "batch"}) args.push_back(a);
  for (const std::string& a : {manifest.string(), std::string("--out"), killed.string()}) args.push_back(a);
  int victim_pid = 0, victim_rank = 0;
  std::string victim_material;
  {
    testing_support::ChildProcess run(MPIEXEC, args, {}, (dir / "killed.log").string());
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (victim_pid == 0 && run.running() && std::chrono::steady_clock::now() < deadline) {
      for (const std::string& name : kMaterials) {
        try {
          const nlohmann::json marker = nlohmann::json::parse(read_text(killed / name / "running.json"));
          if (marker["rank"].get<int>() > 0) {
            victim_pid = marker["pid"].get<int>();
            victim_rank = marker["rank"].get<int>();
            victim_material = name;
            break;
          }
        } catch (const std::exception&) {
          // not there yet, or being written
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    REQUIRE(victim_pid > 0);
    ::kill(victim_pid, SIGKILL);
    const std::optional<int> exit = run.wait_for_exit(std::chrono::seconds(60));
    INFO(read_text(dir / "killed.log"));
    REQUIRE(exit.has_value());
    CHECK(*exit != 0);
  }
  INFO("killed rank " << victim_rank << " (pid " << victim_pid << ") diagnosing " << victim_material);
  check_nothing_half_written(killed);
  CHECK_FALSE(fs::exists(killed / victim_material / "done.json"));

  // The same command again: the interrupted materials are diagnosed again, and say so.
  output.clear();
  REQUIRE(testing_support::run_command(mpirun(3) + batch_args(manifest, killed), output) == 0);
  const nlohmann::json resumed = read_json(killed / "summary.json");
  for (std::size_t i = 0; i < kMaterials.size(); ++i) {
    check_same_material(serial, killed, kMaterials[i]);
    CHECK_FALSE(fs::exists(killed / kMaterials[i] / "running.json"));
    if (kMaterials[i] == victim_material) {
      CHECK_THAT(resumed["materials"][i]["note"].get<std::string>(),
                 Catch::Contains("earlier run stopped") && Catch::Contains("rank " + std::to_string(victim_rank)));
    }
  }
}

TEST_CASE("one diagnosis's refit searches over 3 ranks, and a batch in teams, give the serial verdicts", "[mpi]") {
  // Sheets whose warp bends at 0.4 of the weft: the isotropic base fit misses it, so the
  // orthotropic refit runs, from five starts (refit.h).
  testing_support::TempDir dir("mpi_refits");
  twin::Material truth = sim_hw::lab_specimen("composite").truth;
  truth.bending_rigidity_v_Nm = 0.4 * truth.bending_rigidity_u_Nm;
  const std::vector<std::string> lots = {"lot_a", "lot_b"};
  const fs::path manifest_file = write_batch_inputs(dir, lots, 21, 6, truth);
  const fs::path serial = dir / "serial", teams = dir / "teams";
  std::string output;
  REQUIRE(testing_support::run_command(batch_args(manifest_file, serial), output) == 0);  // serial: no mpirun
  for (const std::string& lot : lots) {
    INFO(output);
    REQUIRE(read_json(serial / lot / "verdict.json")["effect"] == "orthotropic_stiffness");
  }

  // `twin diagnose` with the manifest's options, over 3 ranks: the serial batch's lot_a files.
  output.clear();
  const std::string diagnose = mpirun(3) + " " + TWIN_EXE + " --threads 1 diagnose --train " +
                               (dir / "trials" / "lot_a").string() + " --test " + (dir / "trials" / "test").string() +
                               " --report " + (dir / "diagnose").string() + " --triangles " +
                               std::to_string(kTriangles) + " --path-triangles 0 --refits 1 --effects "
                               "orthotropic_stiffness --noise-mm 0.3 --no-discretisation-check";
  int status = testing_support::run_command(diagnose, output);
  {
    INFO(output);
    REQUIRE(status == 0);
    CHECK_THAT(output, Catch::Contains("5 refit searches over 3 ranks"));
    for (int r = 0; r < 3; ++r) CHECK_THAT(output, Catch::Contains("(rank " + std::to_string(r) + "):"));
    CHECK(read_text(serial / "lot_a" / "verdict.json") == read_text(dir / "diagnose" / "verdict.json"));
    CHECK(read_text(serial / "lot_a" / "material_augmented.json") ==
          read_text(dir / "diagnose" / "material_augmented.json"));
  }

  // The batch in teams of 2 on 3 ranks (teams {0, 1} and {2}): each lot to a team.
  output.clear();
  status = testing_support::run_command(mpirun(3) + batch_args(manifest_file, teams) + " --ranks-per-material 2", output);
  INFO(output);
  REQUIRE(status == 0);
  CHECK_THAT(output, Catch::Contains("2 materials over 3 ranks in teams of 2"));
  for (const std::string& lot : lots) check_same_material(serial, teams, lot);
}

TEST_CASE("plan_grasps over 3 ranks writes the serial run's plan", "[mpi]") {
  testing_support::TempDir dir("mpi_plan");
  nlohmann::json goal = nlohmann::json::parse(R"({
    "sheet": {"width_m": 1.17, "height_m": 0.975, "target_triangles": 500},
    "tool": {"centre_m": [0.0, 0.0], "top_z_m": 0.70, "size_m": [1.3, 1.1]},
    "hold_z_m": 1.0, "max_sag_m": 0.25, "min_clearance_m": 0.05,
    "folds": {"min_bend_radius_m": 0.02, "max_overturned_fraction": 0.0},
    "grippers": ["LEFT", "RIGHT", "CENTER", "MANUAL"],
    "search": {"inset_m": [0.10], "ring_spacing_m": 0.25, "slack_factors": [0.04], "random_candidates": 1,
               "screening_triangles": 250, "finalists": 3, "seed": 3}
  })");
  goal["material_file"] = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/composite_identified.json";
  const fs::path goal_file = dir / "goal.json";
  std::ofstream(goal_file) << goal.dump(2);
  auto plan_command = [&](const std::string& launcher, const fs::path& plan) {
    return launcher + " " + PLAN_GRASPS_EXE + " --goal " + goal_file.string() + " --out " + plan.string() +
           " --verbose";
  };
  std::string serial_output, mpi_output;
  REQUIRE(testing_support::run_command(plan_command("", dir / "serial.json"), serial_output) == 0);
  const int status = testing_support::run_command(plan_command(mpirun(3), dir / "mpi.json"), mpi_output);
  INFO(mpi_output);
  REQUIRE(status == 0);
  nlohmann::json serial = read_json(dir / "serial.json"), spread = read_json(dir / "mpi.json");
  serial.erase("note");  // it holds the run's timings
  spread.erase("note");
  CHECK(serial == spread);
  // Every rank simulated some of the candidates.
  for (int r = 0; r < 3; ++r) CHECK_THAT(mpi_output, Catch::Contains("[rank " + std::to_string(r) + "/3] screen"));
}

TEST_CASE("a twin command that does not spread over ranks refuses to run under mpirun -np 2", "[mpi]") {
  std::string output;
  const int status = testing_support::run_command(
      mpirun(2) + " " + TWIN_EXE + " material " + PREPREG_SOURCE_DIR + "/cell/examples/composite_identified.json", output);
  INFO(output);
  CHECK(status != 0);
  CHECK_THAT(output, Catch::Contains("only 'batch' and 'diagnose' run over MPI ranks"));
}
