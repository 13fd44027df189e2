#include "cell/background_worker.h"

#include <sched.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace cell {
namespace {

// Applies `priority` to the calling thread (sched_setscheduler with pid 0 is the calling
// thread's own policy on Linux). Lowering needs no privilege.
std::string apply_to_this_thread(WorkerPriority priority) {
  if (priority == WorkerPriority::kNormal) return "";
  sched_param parameters{};
  parameters.sched_priority = 0;
  if (sched_setscheduler(0, SCHED_IDLE, &parameters) != 0) {
    return fmt::format("SCHED_IDLE refused: {}", std::strerror(errno));
  }
  return "";
}

}  // namespace

std::optional<WorkerPriority> worker_priority_from_name(const std::string& name) {
  if (name == "normal") return WorkerPriority::kNormal;
  if (name == "idle") return WorkerPriority::kIdle;
  return std::nullopt;
}

BackgroundWorker::BackgroundWorker(WorkerPriority priority)
    : priority_(priority), thread_([this] { run(); }) {}

std::string BackgroundWorker::priority_problem() { return priority_problem_.get(); }

BackgroundWorker::~BackgroundWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void BackgroundWorker::enqueue(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void BackgroundWorker::run() {
  priority_set_.set_value(apply_to_this_thread(priority_));
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;  // stopping, and nothing left
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();
  }
}

}  // namespace cell
