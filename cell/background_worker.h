#pragma once
// One long-lived thread that runs submitted tasks in order, each returning a future. The cell
// runs the twin's step on it beside the tracker every cycle; a thread made per cycle would also
// make OpenMP set up its thread state anew 30 times a second.
//
// A worker may run at idle priority (Linux SCHED_IDLE): it then gets only the CPU time that the
// process's other threads leave, and a waking cycle thread preempts it at once. Threads it
// starts (an OpenMP team of its own) inherit that.

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace cell {

enum class WorkerPriority { kNormal, kIdle };
// "normal" / "idle", as config files and command lines spell them; nullopt for another name.
std::optional<WorkerPriority> worker_priority_from_name(const std::string& name);

class BackgroundWorker {
 public:
  explicit BackgroundWorker(WorkerPriority priority = WorkerPriority::kNormal);
  ~BackgroundWorker();  // finishes the queued tasks, then joins
  BackgroundWorker(const BackgroundWorker&) = delete;
  BackgroundWorker& operator=(const BackgroundWorker&) = delete;

  // Queues `task`; its result (or exception) arrives through the future.
  template <typename F>
  auto submit(F task) -> std::future<decltype(task())> {
    auto packaged = std::make_shared<std::packaged_task<decltype(task())()>>(std::move(task));
    std::future<decltype(task())> result = packaged->get_future();
    enqueue([packaged] { (*packaged)(); });
    return result;
  }

  // Empty once the thread runs at the priority asked for; otherwise why not (it then runs at
  // the normal priority, which is always safe). Waits for the thread to have tried.
  std::string priority_problem();

 private:
  void enqueue(std::function<void()> job);
  void run();

  const WorkerPriority priority_;
  std::promise<std::string> priority_set_;
  std::shared_future<std::string> priority_problem_ = priority_set_.get_future().share();
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace cell
