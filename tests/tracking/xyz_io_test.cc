#include "tracking/xyz_io.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "tests/support/temp_dir.h"

namespace tracking {
namespace {

namespace fs = std::filesystem;

// Each test case's files go to a fresh directory of its own.
class TempDir : public testing_support::TempDir {
 public:
  TempDir() : testing_support::TempDir("tracking_xyz_io_test") {}
};

std::vector<Vec3> parse(const std::string& text, bool allow_nan) {
  std::istringstream in(text);
  return parse_xyz(in, "points.xyz", allow_nan);
}

std::string parse_error(const std::string& text, bool allow_nan) {
  try {
    parse(text, allow_nan);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_CASE("xyz: comments, blank lines, CRLF, signs and exponents", "[xyz]") {
  const std::vector<Vec3> p = parse(
      "# scanner export\n"
      "\n"
      "1 2 3\n"
      "   # indented comment\n"
      "\t-0.5  +1e-3\t2.5E2\r\n"
      "nan nan nan\n",
      /*allow_nan=*/true);
  REQUIRE(p.size() == 3);
  CHECK(p[0] == Vec3(1, 2, 3));
  CHECK(p[1] == Vec3(-0.5, 1e-3, 250.0));
  CHECK(p[2].array().isNaN().all());
}

TEST_CASE("xyz: a bad line is rejected naming file:line", "[xyz]") {
  CHECK_THAT(parse_error("1 2 3\n# c\n1 2\n", false),
             Catch::Contains("points.xyz:3:") && Catch::Contains("3 numbers"));
  CHECK_THAT(parse_error("1 2 3\n1 2 3 4\n", false), Catch::Contains("points.xyz:2:"));
  CHECK_THAT(parse_error("1 2 3\n\n1 two 3\n", false),
             Catch::Contains("points.xyz:3:") && Catch::Contains("\"two\""));
  CHECK_THAT(parse_error("1,2,3\n", false), Catch::Contains("points.xyz:1:"));
  CHECK_THAT(parse_error("1 2 inf\n", false),
             Catch::Contains("points.xyz:1:") && Catch::Contains("not finite"));
  CHECK_THAT(parse_error("0 0 0\nnan nan nan\n", false),
             Catch::Contains("points.xyz:2:") && Catch::Contains("NaN is not allowed"));
  CHECK_THAT(parse_error("1 nan 3\n", true),
             Catch::Contains("points.xyz:1:") && Catch::Contains("all three"));
  CHECK_THAT(parse_error("1 2 3x\n", false), Catch::Contains("points.xyz:1:"));
}

TEST_CASE("xyz: files round-trip exactly and are replaced atomically", "[xyz]") {
  TempDir dir;
  const std::string path = (dir / "markers.xyz").string();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<Vec3> points;
  for (int i = 0; i < 50; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  points[7] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());

  write_xyz_file(path, points, "two header\nlines");
  CHECK_FALSE(fs::exists(path + ".tmp"));
  const std::vector<Vec3> back = read_xyz_file(path, /*allow_nan=*/true);
  REQUIRE(back.size() == points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i == 7) {
      CHECK(back[i].hasNaN());
    } else {
      CHECK(back[i] == points[i]);  // bit-exact: shortest round-trip text
    }
  }
  CHECK_THROWS_WITH(read_xyz_file(path, /*allow_nan=*/false),
                    Catch::Contains(path + ":") && Catch::Contains("NaN"));

  // A failed write (directory missing) throws naming the path and leaves nothing behind.
  const std::string unwritable = (dir / "missing" / "out.xyz").string();
  CHECK_THROWS_WITH(write_xyz_file(unwritable, points), Catch::Contains(unwritable));
  CHECK_THROWS_WITH(read_xyz_file((dir / "absent.xyz").string(), false),
                    Catch::Contains("absent.xyz"));
}

}  // namespace
}  // namespace tracking
