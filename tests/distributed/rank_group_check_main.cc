// Started by mpirun from mpi_runs_test.cc: spreads tasks over the ranks both ways
// (twin/distributed/rank_group.h) and checks, on every rank, that each task ran once, where it
// should, and that its result arrived intact and in order. Exits 0 when every check passed.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <thread>

#include "twin/distributed/byte_codec.h"
#include "twin/distributed/rank_group.h"

namespace {

using twin::distributed::ByteReader;
using twin::distributed::ByteWriter;

// A result that depends on the index only, and says which rank made it.
std::string task_result(int index, int rank) {
  ByteWriter w;
  w.put<std::int32_t>(index).put<std::int32_t>(rank).put(0.1 * index).put_string(std::string(static_cast<std::size_t>(index) * 1000, 'x'));
  return w.take();
}

}  // namespace

int main() {
  const std::unique_ptr<twin::distributed::RankGroup> ranks = twin::distributed::join_ranks();
  const int rank = ranks->rank(), size = ranks->size();
  int failures = 0;
  auto fail = [&](const std::string& what) {
    std::fprintf(stderr, "rank %d: %s\n", rank, what.c_str());
    ++failures;
  };

  const int count = 11;
  const auto mapped = ranks->map_on_every_rank(count, [&](int i) { return task_result(i, rank); });
  if (static_cast<int>(mapped.size()) != count) fail("map_on_every_rank: wrong number of results");
  for (int i = 0; i < static_cast<int>(mapped.size()); ++i) {
    ByteReader r(mapped[i]);
    const int index = r.get<std::int32_t>(), by = r.get<std::int32_t>();
    const double value = r.get<double>();
    const std::string text = r.get_string();
    if (index != i || value != 0.1 * i || text.size() != static_cast<std::size_t>(i) * 1000 || !r.at_end()) {
      fail("map_on_every_rank: result " + std::to_string(i) + " is not task " + std::to_string(i) + "'s");
    }
    if (by != i % size) fail("map_on_every_rank: task " + std::to_string(i) + " ran on rank " + std::to_string(by));
  }

  // Uneven tasks: the first ones longest, so that free ranks take the rest.
  const auto farmed = ranks->farm_to_rank0(count, [&](int i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20 * (count - i)));
    return task_result(i, rank);
  });
  std::set<int> workers;
  if (rank == 0) {
    if (static_cast<int>(farmed.size()) != count) fail("farm_to_rank0: wrong number of results on rank 0");
    for (int i = 0; i < static_cast<int>(farmed.size()); ++i) {
      ByteReader r(farmed[i]);
      const int index = r.get<std::int32_t>();
      workers.insert(r.get<std::int32_t>());
      if (index != i || r.get<double>() != 0.1 * i) fail("farm_to_rank0: result " + std::to_string(i) + " misplaced");
    }
    if (size > 1 && static_cast<int>(workers.size()) < 2) fail("farm_to_rank0: only one rank worked");
  } else if (!farmed.empty()) {
    fail("farm_to_rank0: results on a rank other than 0");
  }

  // Rank 0's bytes reach every rank; farm_to_every_rank's results too.
  if (ranks->broadcast_from_rank0(rank == 0 ? std::string("from rank 0\0!", 13) : std::string("other")) !=
      std::string("from rank 0\0!", 13)) {
    fail("broadcast_from_rank0: not rank 0's bytes");
  }
  const auto everywhere = ranks->farm_to_every_rank(count, [&](int i) { return task_result(i, rank); });
  if (static_cast<int>(everywhere.size()) != count) fail("farm_to_every_rank: wrong number of results");
  for (int i = 0; i < static_cast<int>(everywhere.size()); ++i) {
    ByteReader r(everywhere[i]);
    if (r.get<std::int32_t>() != i) fail("farm_to_every_rank: result " + std::to_string(i) + " misplaced");
  }

  // Teams of two, as `twin batch --ranks-per-material 2` makes them: the leaders farm tasks, and
  // each task is farmed again over the leader's team (on rank 0 from its computing thread), its
  // other ranks following their leader until it says stop.
  std::string teams_line;
  if (size >= 2) {
    twin::distributed::Teams teams = ranks->split_into_teams(2);
    if (teams.team->size() != (rank / 2 * 2 + 1 < size ? 2 : 1)) fail("split_into_teams: wrong team size");
    if ((teams.leaders != nullptr) != (rank % 2 == 0)) fail("split_into_teams: wrong leaders");
    auto team_task = [&](int outer) {
      // Every rank of the team computes part; the sum is the same wherever the parts ran.
      const auto parts = teams.team->farm_to_every_rank(5, [&](int j) {
        ByteWriter w;
        w.put<std::int32_t>(outer * 10 + j);
        return w.take();
      });
      std::int32_t sum = 0;
      for (const std::string& p : parts) sum += ByteReader(p).get<std::int32_t>();
      return sum;
    };
    auto say = [&](std::int32_t v) {
      ByteWriter w;
      w.put(v);
      teams.team->broadcast_from_rank0(w.bytes());
    };
    if (teams.leaders) {
      const int outer_count = 4;
      const auto sums = teams.leaders->farm_to_rank0(outer_count, [&](int outer) {
        say(outer);
        ByteWriter w;
        w.put<std::int32_t>(team_task(outer));
        return w.take();
      });
      say(-1);
      if (rank == 0) {
        if (static_cast<int>(sums.size()) != outer_count) fail("teams: wrong number of results");
        for (int outer = 0; outer < static_cast<int>(sums.size()); ++outer) {
          if (ByteReader(sums[outer]).get<std::int32_t>() != 50 * outer + 10) fail("teams: a wrong sum");
        }
        teams_line = ", " + std::to_string(teams.team_count) + " teams";
      }
    } else {
      for (;;) {
        const std::string bytes = teams.team->broadcast_from_rank0("");
        const std::int32_t outer = ByteReader(bytes).get<std::int32_t>();
        if (outer < 0) break;
        team_task(outer);
      }
    }
  }

  if (rank == 0) {
    std::string who;
    for (int w : workers) who += " " + std::to_string(w);
    std::printf("rank_group_check: %d ranks, farm ran on ranks%s%s, %s\n", size, who.c_str(), teams_line.c_str(),
                failures ? "FAILED" : "ok");
  }
  std::fflush(stdout);
  return failures ? 1 : 0;
}
