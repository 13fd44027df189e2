// join_ranks() of a build with MPI: MPI_COMM_WORLD of the processes mpirun started, and the
// teams split from it (split_into_teams).
//
// Waiting is done by polling with short sleeps (MPI_Test, MPI_Iprobe) rather than in blocking
// calls: OpenMPI's blocking calls spin a core, and a rank that waits for the others (or rank 0's
// main thread, which only hands out work) must leave the cores to the ranks still computing.
// Rank 0's own share of a farm runs on a second thread. Without teams that thread never calls
// MPI; a team's work on it does (on the team's communicator, while the main thread hands out on
// the leaders'), so MPI is started with MPI_THREAD_MULTIPLE where the library has it, and teams
// are refused where it has not.
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "twin/distributed/byte_codec.h"
#include "twin/distributed/rank_group.h"

namespace twin::distributed {
namespace {

constexpr int kResultTag = 1;  // worker -> rank 0: int32 index (-1: first request), then the result
constexpr int kTaskTag = 2;    // rank 0 -> worker: int32 next index, -1: no more
constexpr auto kPollInterval = std::chrono::milliseconds(2);

void wait_sleeping(MPI_Request& request) {
  int done = 0;
  for (;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(kPollInterval);
  }
}

void barrier_sleeping(MPI_Comm comm) {
  MPI_Request request;
  MPI_Ibarrier(comm, &request);
  wait_sleeping(request);
}

[[noreturn]] void abort_run(int rank, int index, const std::string& what) {
  std::fprintf(stderr, "rank %d: task %d threw (tasks must return their failures): %s\n", rank, index, what.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);  // the whole run, not one team
  std::abort();  // MPI_Abort does not return
}

std::string run_or_abort(const Task& task, int index, int rank) {
  try {
    return task(index);
  } catch (const std::exception& e) {
    abort_run(rank, index, e.what());
  }
}

int byte_count(const std::string& bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) throw std::runtime_error("a task's result exceeds 2 GB");
  return static_cast<int>(bytes.size());
}

// Every task's result, in index order; a task without one is a bug of the hand-out, not a result.
std::vector<std::string> all_results(std::vector<std::optional<std::string>> slots, const char* way) {
  std::vector<std::string> results;
  results.reserve(slots.size());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (!slots[i]) throw std::runtime_error(std::string(way) + ": task " + std::to_string(i) + " has no result");
    results.push_back(std::move(*slots[i]));
  }
  return results;
}

// The ranks of one communicator: the world's, or a team's or the team leaders' (split_into_teams).
class MpiGroup : public RankGroup {
 public:
  // `owned`: a communicator split from another, freed with the group.
  MpiGroup(MPI_Comm comm, bool owned, int thread_support) : comm_(comm), owned_(owned), thread_support_(thread_support) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }
  ~MpiGroup() override {
    if (owned_) MPI_Comm_free(&comm_);
  }
  MpiGroup(const MpiGroup&) = delete;
  MpiGroup& operator=(const MpiGroup&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }

  std::vector<std::string> map_on_every_rank(int count, const Task& task) override {
    ByteWriter mine;
    for (int i = rank_; i < count; i += size_) mine.put<std::int32_t>(i).put_string(run_or_abort(task, i, rank_));
    barrier_sleeping(comm_);
    const int length = byte_count(mine.bytes());
    std::vector<int> lengths(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
    MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, comm_);
    long long total = 0;
    for (int r = 0; r < size_; ++r) {
      offsets[r] = static_cast<int>(total);
      total += lengths[r];
    }
    if (total > INT_MAX) throw std::runtime_error("the tasks' results exceed 2 GB together");
    std::string all(static_cast<std::size_t>(total), '\0');
    MPI_Allgatherv(mine.bytes().data(), length, MPI_BYTE, all.data(), lengths.data(), offsets.data(), MPI_BYTE,
                   comm_);
    std::vector<std::optional<std::string>> slots(static_cast<std::size_t>(count));
    ByteReader reader(all);
    while (!reader.at_end()) {
      const int index = reader.get<std::int32_t>();
      if (index < 0 || index >= count) throw std::runtime_error("map_on_every_rank: a rank sent a result for task " + std::to_string(index));
      slots[index] = reader.get_string();
    }
    return all_results(std::move(slots), "map_on_every_rank");
  }

  std::vector<std::string> farm_to_rank0(int count, const Task& task) override {
    return rank_ == 0 ? hand_out(count, task) : work_for_rank0(task);
  }

  std::string broadcast_from_rank0(const std::string& bytes) override {
    std::uint64_t length = rank_ == 0 ? bytes.size() : 0;
    MPI_Request request;
    MPI_Ibcast(&length, 1, MPI_UINT64_T, 0, comm_, &request);
    wait_sleeping(request);
    std::string out = rank_ == 0 ? bytes : std::string(static_cast<std::size_t>(length), '\0');
    // In pieces under 2 GB: MPI counts are ints.
    constexpr std::uint64_t kPiece = 1u << 30;
    for (std::uint64_t at = 0; at < length; at += kPiece) {
      const int n = static_cast<int>(std::min(kPiece, length - at));
      MPI_Ibcast(out.data() + at, n, MPI_BYTE, 0, comm_, &request);
      wait_sleeping(request);
    }
    return out;
  }

 private:
  // Rank 0: its main thread answers the workers; a second thread takes tasks from the same
  // counter. Either way a task is handed out once, in index order.
  std::vector<std::string> hand_out(int count, const Task& task) {
    std::mutex mutex;
    int next = 0;
    std::vector<std::optional<std::string>> slots(static_cast<std::size_t>(count));
    auto take = [&] {
      std::lock_guard lock(mutex);
      return next < count ? next++ : -1;
    };
    std::atomic<bool> local_done{false};
    std::optional<std::pair<int, std::string>> local_failure;
    const int threads = omp_get_max_threads();  // the main thread's setting (--threads); a new thread starts from the default
    std::thread local([&] {
      omp_set_num_threads(threads);
      for (int i; (i = take()) >= 0;) {
        try {
          std::string result = task(i);
          std::lock_guard lock(mutex);
          slots[i] = std::move(result);
        } catch (const std::exception& e) {
          std::lock_guard lock(mutex);
          local_failure.emplace(i, e.what());
          break;
        }
      }
      local_done = true;
    });
    int working = size_ - 1;
    std::string buffer;
    while (working > 0 || !local_done) {
      {
        std::lock_guard lock(mutex);
        if (local_failure) abort_run(0, local_failure->first, local_failure->second);
      }
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, kResultTag, comm_, &arrived, &status);
      if (!arrived) {
        std::this_thread::sleep_for(kPollInterval);
        continue;
      }
      int length = 0;
      MPI_Get_count(&status, MPI_BYTE, &length);
      buffer.resize(static_cast<std::size_t>(length));
      MPI_Recv(buffer.data(), length, MPI_BYTE, status.MPI_SOURCE, kResultTag, comm_, MPI_STATUS_IGNORE);
      ByteReader reader(buffer);
      const int index = reader.get<std::int32_t>();
      if (index >= count) throw std::runtime_error("farm_to_rank0: a rank sent a result for task " + std::to_string(index));
      if (index >= 0) {
        std::string result = reader.get_string();
        std::lock_guard lock(mutex);
        slots[index] = std::move(result);
      }
      const std::int32_t assigned = take();
      MPI_Send(&assigned, 1, MPI_INT32_T, status.MPI_SOURCE, kTaskTag, comm_);
      if (assigned < 0) --working;
    }
    local.join();
    if (local_failure) abort_run(0, local_failure->first, local_failure->second);
    return all_results(std::move(slots), "farm_to_rank0");
  }

  std::vector<std::string> work_for_rank0(const Task& task) {
    ByteWriter message;
    message.put<std::int32_t>(-1);
    for (;;) {
      const std::string bytes = message.take();
      MPI_Request sent;
      MPI_Isend(bytes.data(), byte_count(bytes), MPI_BYTE, 0, kResultTag, comm_, &sent);
      wait_sleeping(sent);
      std::int32_t index = -1;
      MPI_Request received;
      MPI_Irecv(&index, 1, MPI_INT32_T, 0, kTaskTag, comm_, &received);
      wait_sleeping(received);
      if (index < 0) return {};
      message = ByteWriter();
      message.put<std::int32_t>(index).put_string(run_or_abort(task, index, rank_));
    }
  }

  Teams split_into_teams(int team_size) override {
    check_team_size(team_size, size_);
    if (thread_support_ < MPI_THREAD_MULTIPLE) {
      throw std::runtime_error("teams of ranks need an MPI with MPI_THREAD_MULTIPLE (a team's work on rank 0's "
                               "computing thread calls MPI); this one has not: run with --ranks-per-material 1");
    }
    MPI_Comm team, leaders;
    MPI_Comm_split(comm_, rank_ / team_size, rank_, &team);
    MPI_Comm_split(comm_, rank_ % team_size == 0 ? 0 : MPI_UNDEFINED, rank_, &leaders);
    Teams teams;
    teams.team = std::make_unique<MpiGroup>(team, true, thread_support_);
    if (leaders != MPI_COMM_NULL) teams.leaders = std::make_unique<MpiGroup>(leaders, true, thread_support_);
    teams.team_index = rank_ / team_size;
    teams.team_count = (size_ + team_size - 1) / team_size;
    return teams;
  }

 protected:
  MPI_Comm comm_;
  bool owned_ = false;
  int thread_support_ = MPI_THREAD_FUNNELED;
  int rank_ = 0, size_ = 1;
};

// Starts MPI before the world's group is made, and finishes it after the group (and every team
// split from it, which must be gone by then) is done with.
struct MpiRuntime {
  int thread_support = 0;
  MpiRuntime() {
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &thread_support);
    if (thread_support < MPI_THREAD_FUNNELED) {
      MPI_Finalize();
      throw std::runtime_error("this MPI does not let a second thread compute beside MPI (MPI_THREAD_FUNNELED)");
    }
  }
  ~MpiRuntime() { MPI_Finalize(); }
};

class MpiWorld final : private MpiRuntime, public MpiGroup {
 public:
  MpiWorld() : MpiRuntime(), MpiGroup(MPI_COMM_WORLD, false, thread_support) {}
  ~MpiWorld() override {
    barrier_sleeping(MPI_COMM_WORLD);  // no rank spins in MPI_Finalize while another still computes
  }
};

}  // namespace

bool built_with_mpi() { return true; }

std::unique_ptr<RankGroup> join_ranks() {
  if (!launched_by_mpirun()) return std::make_unique<SingleProcess>();
  return std::make_unique<MpiWorld>();
}

}  // namespace twin::distributed
