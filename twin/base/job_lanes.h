#pragma once
// A few lanes (OpenMP threads) that share a queue of jobs while lane 0 first runs a lead task
// that may add jobs as it goes: the fresh simulation of a trial follows its stages in order on
// lane 0 while the other lane already lets stages go from their scans (trial_evaluator.cc).
//
// Why lanes and not the element loops' own threads: on the twin's meshes (1.5k triangles in
// identification) a parallel element loop is too short to pay for its fork and join, and a
// trial's fresh simulation ran only 1.16x faster on two threads than on one (measured). Whole
// solves side by side keep both cores busy. The lanes are one OpenMP parallel region, so
// everything parallel inside a job (the element loops, CHOLMOD's loops) is nested and runs on
// the job's own thread (max active levels 1, which sparse_cholesky.cc sets and run_lanes
// asserts), and OMP_NUM_THREADS=1 gives one lane that does everything in order.
//
// A job gets its lane number so it can use that lane's own copy of anything mutable (a model).

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>

namespace twin {

class JobQueue {
 public:
  using Job = std::function<void(int lane)>;
  void push(Job job);

 private:
  friend void run_lanes(int max_lanes, JobQueue& queue, const std::function<void()>& lead);
  // Blocks until a job is available (true) or the queue is closed and empty (false).
  bool next(Job& job);
  void close();
  void reopen();

  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Job> jobs_;
  bool closed_ = false;
};

// Runs `lead` on lane 0 while lanes 1.. run queued jobs; once `lead` returns lane 0 runs jobs
// too, and run_lanes returns when `lead` has returned and the queue is empty. Uses at most
// `max_lanes` threads (fewer when OpenMP allows fewer, one when called inside an active
// parallel region). The first exception a lead or job throws is rethrown here after every lane
// has stopped; jobs still queued then are dropped.
void run_lanes(int max_lanes, JobQueue& queue, const std::function<void()>& lead);

// How many lanes run_lanes(max_lanes, ...) would use if called here.
int available_lanes(int max_lanes);

}  // namespace twin
