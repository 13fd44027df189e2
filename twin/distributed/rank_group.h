#pragma once
// The processes of one run of a command, and how independent work is spread over them. Under
// `mpirun -np N` (Debian's OpenMPI) there are N ranks, one process each; otherwise there is one,
// and both ways of spreading work below run the tasks in order in this process, exactly as a
// serial loop would (twin/distributed/single_process.cc).
//
// A task returns its result as bytes (byte_codec.h, or JSON text). Every result, computed here
// or on another rank, is decoded from those bytes, so a result does not depend on where it ran.
// A task must not throw: it returns its failure in its result. One that throws anyway stops the
// whole run (MPI_Abort under mpirun) after printing which task and why, so no rank waits forever
// for a result that will never come.
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace twin::distributed {

using Task = std::function<std::string(int index)>;

struct Teams;

class RankGroup {
 public:
  virtual ~RankGroup() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;

  // Every rank calls it at the same point with the same count and an equivalent task (the same
  // program on the same inputs). Task i runs on rank i % size; every rank gets every result, in
  // index order. For tasks of similar cost whose results every rank goes on with (a grasp
  // planner's candidate simulations).
  virtual std::vector<std::string> map_on_every_rank(int count, const Task& task) = 0;

  // Tasks handed out one at a time to whichever rank is free, rank 0 included (it works on a
  // thread of its own while its main thread hands out); results in index order on rank 0, empty
  // vectors elsewhere. For tasks of very different cost (whole materials of a batch).
  virtual std::vector<std::string> farm_to_rank0(int count, const Task& task) = 0;

  // Every rank calls it at the same point; every rank returns rank 0's `bytes` (the others'
  // are ignored).
  virtual std::string broadcast_from_rank0(const std::string& bytes) = 0;

  // farm_to_rank0, then rank 0's results sent to every rank: tasks of very different cost whose
  // results every rank goes on with (the searches of a diagnosis's refits).
  std::vector<std::string> farm_to_every_rank(int count, const Task& task);

  // Every rank calls it at the same point with the same size: the ranks in consecutive teams of
  // `team_size` (the last one smaller when it does not divide), for work spread first over teams
  // and then inside each (a batch's materials over teams, each material's refit searches over
  // its team). Throws std::invalid_argument unless 1 <= team_size <= size(). The teams must be
  // destroyed before this group.
  virtual Teams split_into_teams(int team_size) = 0;
};

struct Teams {
  std::unique_ptr<RankGroup> team;     // this rank's team; its rank 0 leads it
  std::unique_ptr<RankGroup> leaders;  // the teams' leaders (on a leader; null on the others)
  int team_index = 0, team_count = 1;
};

// The check of split_into_teams' argument.
void check_team_size(int team_size, int ranks);

// This process alone.
class SingleProcess final : public RankGroup {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<std::string> map_on_every_rank(int count, const Task& task) override;
  std::vector<std::string> farm_to_rank0(int count, const Task& task) override;
  std::string broadcast_from_rank0(const std::string& bytes) override { return bytes; }
  Teams split_into_teams(int team_size) override;
};

// True when this process was started by mpirun (OpenMPI's OMPI_COMM_WORLD_SIZE or a PMI
// launcher's PMI_SIZE in the environment); `ranks` is then that size.
bool launched_by_mpirun(int* ranks = nullptr);

// Whether this build has MPI (libopenmpi-dev found when cmake configured it).
bool built_with_mpi();

// The ranks of this run: MPI's world when launched by mpirun (MPI started here and finished
// when the returned object is destroyed: destroy it last, on every rank), else a SingleProcess.
// Throws std::runtime_error when launched by mpirun with more than one rank but this build has
// no MPI (each process would otherwise do the whole job on its own).
std::unique_ptr<RankGroup> join_ranks();

}  // namespace twin::distributed
