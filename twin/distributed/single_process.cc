#include <cstdlib>
#include <stdexcept>
#include <string>

#include "twin/distributed/byte_codec.h"
#include "twin/distributed/rank_group.h"

namespace twin::distributed {

std::vector<std::string> SingleProcess::map_on_every_rank(int count, const Task& task) {
  std::vector<std::string> results;
  results.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) results.push_back(task(i));
  return results;
}

std::vector<std::string> SingleProcess::farm_to_rank0(int count, const Task& task) {
  return map_on_every_rank(count, task);
}

std::vector<std::string> RankGroup::farm_to_every_rank(int count, const Task& task) {
  std::vector<std::string> results = farm_to_rank0(count, task);
  if (size() == 1) return results;
  ByteWriter all;
  for (const std::string& r : results) all.put_string(r);
  const std::string bytes = broadcast_from_rank0(all.bytes());
  ByteReader reader(bytes);
  results.clear();
  for (int i = 0; i < count; ++i) results.push_back(reader.get_string());
  if (!reader.at_end()) throw std::runtime_error("farm_to_every_rank: rank 0 sent more results than tasks");
  return results;
}

void check_team_size(int team_size, int ranks) {
  if (team_size < 1 || team_size > ranks) {
    throw std::invalid_argument("teams of " + std::to_string(team_size) + " ranks: expected 1 to the " +
                                std::to_string(ranks) + " rank(s) of this run");
  }
}

Teams SingleProcess::split_into_teams(int team_size) {
  check_team_size(team_size, 1);
  Teams teams;
  teams.team = std::make_unique<SingleProcess>();
  teams.leaders = std::make_unique<SingleProcess>();
  return teams;
}

bool launched_by_mpirun(int* ranks) {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const char* value = std::getenv(name)) {
      if (ranks) *ranks = std::atoi(value);
      return true;
    }
  }
  if (ranks) *ranks = 1;
  return false;
}

}  // namespace twin::distributed
