#include "cell/background_worker.h"

#include <sched.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

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

int restore_normal_priority_of_all_threads() {
  int refused = 0;
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", error)) {
    const int tid = std::atoi(task.path().filename().c_str());
    if (tid <= 0 || sched_getscheduler(tid) != SCHED_IDLE) continue;
    sched_param parameters{};
    parameters.sched_priority = 0;
    refused += sched_setscheduler(tid, SCHED_OTHER, &parameters) != 0;
  }
  return refused;
}

std::optional<WorkerPriority> worker_priority_from_name(const std::string& name) {
  if (name == "normal") return WorkerPriority::kNormal;
  if (name == "idle") return WorkerPriority::kIdle;
  return std::nullopt;
}

BackgroundWorker::BackgroundWorker(WorkerPriority priority) {
  std::promise<std::string> priority_set;
  priority_problem_ = priority_set.get_future().share();
  thread_ = std::thread(&BackgroundWorker::run, state_, priority, std::move(priority_set));
}

std::string BackgroundWorker::priority_problem() { return priority_problem_.get(); }

BackgroundWorker::~BackgroundWorker() {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stopping = true;
  }
  state_->wake.notify_one();
  if (thread_.joinable()) thread_.join();
}

bool BackgroundWorker::finish_or_let_go(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(state_->mutex);
  state_->jobs.clear();
  if (state_->idle.wait_for(lock, timeout, [this] { return !state_->running; })) return true;
  state_->stopping = true;  // it ends after its task; the state lives as long as it does
  lock.unlock();
  state_->wake.notify_one();
  if (thread_.joinable()) thread_.detach();
  return false;
}

void BackgroundWorker::enqueue(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->jobs.push_back(std::move(job));
  }
  state_->wake.notify_one();
}

void BackgroundWorker::run(std::shared_ptr<State> state, WorkerPriority priority,
                           std::promise<std::string> priority_set) {
  priority_set.set_value(apply_to_this_thread(priority));
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(state->mutex);
      state->running = false;
      state->idle.notify_all();
      state->wake.wait(lock, [&] { return state->stopping || !state->jobs.empty(); });
      if (state->jobs.empty()) return;  // stopping, and nothing left
      job = std::move(state->jobs.front());
      state->jobs.pop_front();
      state->running = true;
    }
    job();
  }
}

}  // namespace cell
