// End-to-end runs of the extract_markers executable (path from CMake): exit status, output file
// and the file:line message on bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "synthetic_scan.h"
#include "tracking/xyz_io.h"

namespace tracking {
namespace {

namespace fs = std::filesystem;

struct Run {
  int status = -1;
  std::string out, err;
};

Run run_tool(const std::string& arguments, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command = std::string(EXTRACT_MARKERS_EXE) + " " + arguments + " >" +
                              out.string() + " 2>" + err.string();
  const int raw = std::system(command.c_str());
  Run r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream o(out), e(err);
  std::stringstream os, es;
  os << o.rdbuf();
  es << e.rdbuf();
  r.out = os.str();
  r.err = es.str();
  return r;
}

TEST_CASE(
    "extract_markers: a scan in, markers in manifest order out, bad input is status 2",
    "[tool]") {
  const fs::path dir = fs::temp_directory_path() /
                       ("tracking_tool_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);

  // Four markers on a plane facing +z; marker 2 is not in the scan.
  std::vector<testing::SheetMarker> markers;
  for (int i = 0; i < 4; ++i) markers.push_back({Vec3(0.05 * i, 0.0, 1.0), Vec3::UnitZ()});
  testing::ScanSettings settings;
  settings.viewpoint_m = Vec3(0.1, 0.0, 2.0);
  std::mt19937 rng(21);
  std::vector<Vec3> scan;
  std::vector<Vec3> guide;
  for (int i = 0; i < 4; ++i) {
    if (i != 2) {
      const std::vector<Vec3> dome = testing::scan_dome(markers[i], settings, rng);
      scan.insert(scan.end(), dome.begin(), dome.end());
    }
    guide.push_back(markers[i].base_m + Vec3(0.003, -0.002, 0.001));
  }
  write_xyz_file((dir / "scan.xyz").string(), scan);
  write_xyz_file((dir / "guide.xyz").string(), guide);

  const std::string files = "--scan " + (dir / "scan.xyz").string() + " --guide " +
                            (dir / "guide.xyz").string() + " --out " +
                            (dir / "markers.xyz").string();
  const Run ok = run_tool(files + " --viewpoint 0.1 0 2 --gate-m 0.01", dir);
  INFO(ok.out << ok.err);
  REQUIRE(ok.status == 0);
  CHECK_THAT(ok.out, Catch::Contains("matched     3 of 4 markers, 1 missing"));
  const std::vector<Vec3> found = read_xyz_file((dir / "markers.xyz").string(), true);
  REQUIRE(found.size() == 4);
  for (int i = 0; i < 4; ++i) {
    if (i == 2) {
      CHECK(found[i].hasNaN());
    } else {
      CHECK((found[i] - markers[i].base_m).norm() < 0.2e-3);
    }
  }
  CHECK_FALSE(fs::exists(dir / "markers.xyz.tmp"));

  // A malformed guide line: status 2, file:line on stderr, the old output left alone.
  {
    std::ofstream bad(dir / "guide.xyz");
    bad << "# guide\n0 0 1\n0.05 0 1 extra\n";
  }
  const Run bad = run_tool(files, dir);
  CHECK(bad.status == 2);
  CHECK_THAT(bad.err, Catch::Contains((dir / "guide.xyz").string() + ":3:"));
  CHECK(read_xyz_file((dir / "markers.xyz").string(), true).size() == 4);

  // A bad option value and a missing required option are bad input too.
  CHECK(run_tool(files + " --marker-radius-m -1", dir).status == 2);
  CHECK(run_tool("--scan " + (dir / "scan.xyz").string(), dir).status == 2);

  fs::remove_all(dir);
}

}  // namespace
}  // namespace tracking
