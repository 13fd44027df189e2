#include "twin/base/job_lanes.h"
#include "twin/base/cancellation.h"

#include <omp.h>

#include <algorithm>
#include <exception>

namespace twin {

void JobQueue::push(Job job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  ready_.notify_one();
}

bool JobQueue::next(Job& job) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [&] { return !jobs_.empty() || closed_; });
  if (jobs_.empty()) return false;
  job = std::move(jobs_.front());
  jobs_.pop_front();
  return true;
}

void JobQueue::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

void JobQueue::reopen() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = false;
}

int available_lanes(int max_lanes) {
  if (omp_get_active_level() >= omp_get_max_active_levels()) return 1;
  return std::max(1, std::min(max_lanes, omp_get_max_threads()));
}

void run_lanes(int max_lanes, JobQueue& queue, const std::function<void()>& lead) {
  const int lanes = available_lanes(max_lanes);
  // Parallel loops inside the jobs must nest inactive (one thread each), or every lane would
  // open a team of its own on the same cores.
  omp_set_max_active_levels(1);
  queue.reopen();
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto record = [&] {
    std::lock_guard<std::mutex> lock(failure_mutex);
    if (!failure) failure = std::current_exception();
  };
  const auto failed = [&] {
    std::lock_guard<std::mutex> lock(failure_mutex);
    return failure != nullptr;
  };
  // The lanes honour the caller's cancellation (cancellation.h): the flag is thread-local.
  const std::atomic<bool>* cancel = current_cancellation_flag();
#pragma omp parallel num_threads(lanes)
  {
    const CancellationScope cancellation(cancel);
    const int lane = omp_get_thread_num();
    if (lane == 0) {
      try {
        lead();
      } catch (...) {
        record();
      }
      queue.close();  // no more jobs: the lanes stop when the queue is empty
    }
    JobQueue::Job job;
    while (queue.next(job)) {
      if (failed()) continue;  // drain without running
      try {
        job(lane);
      } catch (...) {
        record();
      }
    }
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace twin
