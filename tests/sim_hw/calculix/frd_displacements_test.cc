// Reading ccx's result file: the displacement blocks per step and increment, errors by line.

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "sim_hw/calculix/frd_displacements.h"

namespace cx = sim_hw::calculix;

namespace {

// One DISP block in ccx's layout (fixed columns, E12.5 values).
std::string block(int step, int increment, double time, double d) {
  std::string s = fmt::format("    1PSTEP{:>26d}{:>12d}{:>12d}\n", step * 10 + increment, increment, step);
  s += fmt::format("  100CL  101{:12.5E}{:>12d}                     0    1           1\n", time, 2);
  s += " -4  DISP        4    1\n -5  D1          1    2    1    0\n -5  D2          1    2    2    0\n"
       " -5  D3          1    2    3    0\n -5  ALL         1    2    0    0    1ALL\n";
  for (int n = 1; n <= 2; ++n) s += fmt::format(" -1{:>10d}{:12.5E}{:12.5E}{:12.5E}\n", n, d * n, -d, 0.5 * d);
  return s + " -3\n";
}

std::string write(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST_CASE("the frd reader takes every displacement block and the last of each step") {
  const std::string path = write("calculix_frd_test.frd", "    1C\n    2C                             2                                     1\n"
                                 " -1         1 0.00000E+00 0.00000E+00 0.00000E+00\n -3\n" +
                                 block(1, 1, 0.5, 0.001) + block(1, 2, 1.0, 0.002) + block(2, 1, 1.0, -0.003) + "9999\n");
  const auto blocks = cx::read_frd_displacements(path);
  REQUIRE(blocks.size() == 3);
  CHECK(blocks[0].step == 1);
  CHECK(blocks[0].increment == 1);
  CHECK(blocks[0].total_time == Approx(0.5));
  CHECK(blocks[1].displacement_m.at(2).x() == Approx(0.004));
  const auto last = cx::last_of_each_step(blocks);
  REQUIRE(last.size() == 2);
  CHECK(last[0].increment == 2);
  CHECK(last[1].displacement_m.at(1).y() == Approx(0.003));
  CHECK(last[1].displacement_m.at(1).z() == Approx(-0.0015));
  std::remove(path.c_str());
}

TEST_CASE("the frd reader names the line it cannot read and a block cut short") {
  std::string bad = block(1, 1, 1.0, 0.001);
  bad.replace(bad.find(" -1         2") + 13, 12, "  garbage!! ");
  const std::string path = write("calculix_frd_bad.frd", bad);
  CHECK_THROWS_WITH(cx::read_frd_displacements(path), Catch::Contains("calculix_frd_bad.frd:9") && Catch::Contains("not a number"));
  std::string cut = block(1, 1, 1.0, 0.001);
  cut.resize(cut.rfind(" -3"));
  const std::string cut_path = write("calculix_frd_cut.frd", cut);
  CHECK_THROWS_WITH(cx::read_frd_displacements(cut_path), Catch::Contains("not closed"));
  CHECK_THROWS_WITH(cx::read_frd_displacements("/nonexistent/x.frd"), Catch::Contains("cannot open"));
  std::remove(path.c_str());
  std::remove(cut_path.c_str());
}
