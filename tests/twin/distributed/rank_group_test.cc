// The serial side of twin/distributed (issue 38 item 4): one process runs every task in order,
// both ways, and results cross ranks as bytes that decode to the very values (byte_codec.h).
// The MPI side runs under mpirun in tests/distributed/mpi_runs_test.cc.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

#include "twin/distributed/byte_codec.h"
#include "twin/distributed/rank_group.h"

using twin::distributed::ByteReader;
using twin::distributed::ByteWriter;

TEST_CASE("bytes carry numbers bit for bit, strings and arrays whole, and a short message is an error",
          "[distributed]") {
  const double values[] = {0.1, -0.0, std::numeric_limits<double>::denorm_min(), 1e308, std::nan("")};
  ByteWriter w;
  w.put<int>(-7).put(0.1 + 0.2).put_string(std::string("a\0b|\n", 5)).put_doubles(values, 5).put_string("");
  const std::string bytes = w.bytes();
  ByteReader r(bytes);
  CHECK(r.get<int>() == -7);
  CHECK(r.get<double>() == 0.1 + 0.2);  // exactly, not approximately
  CHECK(r.get_string() == std::string("a\0b|\n", 5));
  const std::vector<double> back = r.get_doubles();
  REQUIRE(back.size() == 5);
  for (int i = 0; i < 4; ++i) CHECK(std::memcmp(&back[i], &values[i], sizeof(double)) == 0);
  CHECK(std::isnan(back[4]));
  CHECK(std::signbit(back[1]));
  CHECK(r.get_string().empty());
  CHECK(r.at_end());
  CHECK_THROWS_WITH(r.get<int>(), Catch::Contains("ends early"));

  const std::string cut = bytes.substr(0, sizeof(int) + sizeof(double) + 10);
  ByteReader truncated_string(cut);
  truncated_string.get<int>();
  truncated_string.get<double>();
  CHECK_THROWS_WITH(truncated_string.get_string(), Catch::Contains("ends early"));
  ByteWriter huge;
  huge.put<std::uint64_t>(std::uint64_t{1} << 60);  // an array length no message could hold
  ByteReader lying(huge.bytes());
  CHECK_THROWS_WITH(lying.get_doubles(), Catch::Contains("longer than its message"));
}

TEST_CASE("one process runs every task in order, both ways", "[distributed]") {
  twin::distributed::SingleProcess one;
  CHECK(one.rank() == 0);
  CHECK(one.size() == 1);
  std::vector<int> ran;
  auto task = [&](int i) {
    ran.push_back(i);
    return std::to_string(i * i);
  };
  CHECK(one.map_on_every_rank(4, task) == std::vector<std::string>{"0", "1", "4", "9"});
  CHECK(one.farm_to_rank0(3, task) == std::vector<std::string>{"0", "1", "4"});
  CHECK(ran == std::vector<int>{0, 1, 2, 3, 0, 1, 2});
  CHECK(one.map_on_every_rank(0, task).empty());
}

TEST_CASE("one process farms to every rank, broadcasts to itself, and is one team of one", "[distributed]") {
  twin::distributed::SingleProcess one;
  std::vector<int> ran;
  CHECK(one.farm_to_every_rank(3, [&](int i) {
    ran.push_back(i);
    return std::string(static_cast<std::size_t>(i), 'x');
  }) == std::vector<std::string>{"", "x", "xx"});
  CHECK(ran == std::vector<int>{0, 1, 2});
  CHECK(one.broadcast_from_rank0(std::string("a\0b", 3)) == std::string("a\0b", 3));
  const twin::distributed::Teams teams = one.split_into_teams(1);
  REQUIRE(teams.team);
  REQUIRE(teams.leaders);
  CHECK(teams.team->size() == 1);
  CHECK(teams.team_count == 1);
  CHECK_THROWS_WITH(one.split_into_teams(2), Catch::Contains("teams of 2 ranks") && Catch::Contains("1 rank(s)"));
  CHECK_THROWS_AS(one.split_into_teams(0), std::invalid_argument);
}
