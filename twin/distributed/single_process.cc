#include <cstdlib>
#include <string>

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
