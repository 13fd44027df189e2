// join_ranks() of a build without MPI: one process, and a clear refusal under mpirun -np N > 1.
#include <stdexcept>
#include <string>

#include "twin/distributed/rank_group.h"

namespace twin::distributed {

bool built_with_mpi() { return false; }

std::unique_ptr<RankGroup> join_ranks() {
  int ranks = 1;
  if (launched_by_mpirun(&ranks) && ranks > 1) {
    throw std::runtime_error("started by mpirun with " + std::to_string(ranks) +
                             " ranks, but this build has no MPI (libopenmpi-dev was not found when cmake "
                             "configured it): install it and reconfigure, or run without mpirun");
  }
  return std::make_unique<SingleProcess>();
}

}  // namespace twin::distributed
