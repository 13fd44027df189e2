// The discrepancy analysis of a cell run's log (cell/cell_log_cycles.h, `diagnose_cell_log`):
// a log written with LCM's LogFile API, as lcm-logger writes it, of the fake cell's mesh hanging
// in a plane, tracked with 0.5 mm noise, with an 8 mm bulge the prediction lacks in four
// cycles, an unpaired sheet and a restart of the cell. The reader must pair the sheets by
// cycle, and the tool must flag exactly the bulging cycles.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <random>
#include <string>

#include "cell/cell_config.h"
#include "cell/cell_log_cycles.h"
#include "tests/support/lcm_log_writer.h"
#include "tests/support/run_command.h"
#include "tests/support/temp_dir.h"

namespace {

const std::string kConfig = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/fake_cell.json";

const twin::SheetMesh& mesh() {
  static const twin::SheetMesh m = cell::read_cell_config(kConfig).sheet.mesh;
  return m;
}

prepreg_lcm::sheet_state_t sheet(std::int64_t cycle, std::int64_t utime, std::int8_t source, double bulge_m,
                                 std::mt19937& rng, int vertices) {
  std::normal_distribution<double> noise(0.0, 0.5e-3);
  prepreg_lcm::sheet_state_t s;
  s.utime = utime;
  s.cycle_id = cycle;
  s.source = source;
  s.num_vertices = vertices;
  const bool observed = source == prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  for (int v = 0; v < vertices; ++v) {
    const twin::Vec2 uv = mesh().rest_uv[v % mesh().vertex_count()];
    double y = 0.0;
    if (observed) y += bulge_m * std::exp(-(uv - twin::Vec2(0.4, 0.4)).squaredNorm() / (2 * 0.1 * 0.1));
    const twin::Vec3 p(uv.x(), y, 1.6 - uv.y());
    const twin::Vec3 n = observed ? twin::Vec3(noise(rng), noise(rng), noise(rng)) : twin::Vec3::Zero();
    s.x_m.push_back(static_cast<float>(p.x() + n.x()));
    s.y_m.push_back(static_cast<float>(p.y() + n.y()));
    s.z_m.push_back(static_cast<float>(p.z() + n.z()));
  }
  s.num_observed_flags = observed ? vertices : 0;
  if (observed) s.vertex_observed.assign(vertices, true);
  s.coverage = 1.0f;
  return s;
}

constexpr std::int64_t kStart_us = 1'800'000'000'000'000;

// Run 1: cycles 0-19 (bulge in 12-15), then cycle 20 observed only; run 2 (the cell started
// again): cycles 0-2.
void write_run_log(const std::string& path, int vertices) {
  testing_support::LcmLogWriter log(path);
  std::mt19937 rng(3);
  const auto cycle = [&](std::int64_t id, std::int64_t t, double bulge, bool predicted) {
    log.write("SHEET_OBSERVED", t, sheet(id, t, prepreg_lcm::sheet_state_t::SOURCE_OBSERVED, bulge, rng, vertices));
    if (predicted) {
      log.write("SHEET_PREDICTED", t + 1000,
                sheet(id, t + 1000, prepreg_lcm::sheet_state_t::SOURCE_PREDICTED, 0, rng, vertices));
    }
  };
  for (int id = 0; id < 20; ++id) cycle(id, kStart_us + id * 50'000, id >= 12 && id < 16 ? 8e-3 : 0.0, true);
  cycle(20, kStart_us + 20 * 50'000, 0.0, false);
  for (int id = 0; id < 3; ++id) cycle(id, kStart_us + 5'000'000 + id * 50'000, 0.0, true);
}

}  // namespace

TEST_CASE("a cell log's sheets are paired by cycle, across a restart of the cell", "[cell_log]") {
  testing_support::TempDir dir("cell_log_read");
  const std::string log = (dir / "run.lcmlog").string();
  write_run_log(log, mesh().vertex_count());
  const cell::LoggedCycles read = cell::read_logged_cycles(log, mesh().vertex_count());
  CHECK(read.observed == 24);
  CHECK(read.predicted == 23);
  CHECK(read.unpaired == 1);
  CHECK(read.runs == 2);
  REQUIRE(read.cycles.size() == 23);
  CHECK(read.cycles[19].cycle_id == 19);
  CHECK(read.cycles[20].cycle_id == 21);  // the second run's ids follow the first's (0-20)
  CHECK(read.cycles[19].time_s == Approx(0.95));
  CHECK(read.cycles[0].seen.size() == static_cast<std::size_t>(mesh().vertex_count()));
  // Sheets of another mesh are counted, not paired.
  const cell::LoggedCycles other = cell::read_logged_cycles(log, mesh().vertex_count() + 1);
  CHECK(other.cycles.empty());
  CHECK(other.other_mesh == 23);
  CHECK_THROWS_WITH(cell::read_logged_cycles((dir / "missing.lcmlog").string(), 3), Catch::Contains("missing.lcmlog"));
}

TEST_CASE("diagnose_cell_log flags the cycles where the tracked sheet bulges", "[cell_log]") {
  testing_support::TempDir dir("cell_log_diagnose");
  const std::string log = (dir / "run.lcmlog").string();
  write_run_log(log, mesh().vertex_count());
  std::string output;
  const std::string out = (dir / "report").string();
  const std::string exe = DIAGNOSE_CELL_LOG_EXE;
  const int status = testing_support::run_command(
      exe + " " + log + " --config " + kConfig + " --report " + out + " --noise-mm 0.5", output);
  INFO(output);
  REQUIRE(status == 0);
  CHECK(output.find("disagree in 4 of 23") != std::string::npos);
  std::ifstream in(dir / "report" / "cycles.json");
  REQUIRE(in.good());
  const nlohmann::json j = nlohmann::json::parse(in);
  REQUIRE(j["cycles"].size() == 23);
  for (const auto& c : j["cycles"]) {
    const int id = c["cycle"];
    INFO("cycle " << id);
    CHECK(c["significant"].get<bool>() == (id >= 12 && id < 16));
  }
  CHECK(std::filesystem::exists(dir / "report" / "report.md"));

  // A log of another mesh: refused, naming the log and the mesh.
  const std::string other = (dir / "other.lcmlog").string();
  write_run_log(other, mesh().vertex_count() - 1);
  std::string refused;
  CHECK(testing_support::run_command(exe + " " + other + " --config " + kConfig + " --report " + out, refused) == 1);
  CHECK(refused.find("other.lcmlog") != std::string::npos);
  CHECK(refused.find("no cycle with both sheets on the config's mesh") != std::string::npos);
  // The first report is still there.
  CHECK(std::filesystem::exists(dir / "report" / "cycles.json"));
}
