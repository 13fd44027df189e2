#pragma once
// One long-lived thread that runs submitted tasks in order, each returning a future. The cell
// runs the twin's step on it beside the tracker every cycle; a thread made per cycle would also
// make OpenMP set up its thread state anew 30 times a second.
//
// A worker may run at idle priority (Linux SCHED_IDLE): it then gets only the CPU time that the
// process's other threads leave, and a waking cycle thread preempts it at once. Threads it
// starts (an OpenMP team of its own) inherit that.

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace cell {

enum class WorkerPriority { kNormal, kIdle };

// Puts every thread of this process back at the normal policy (SCHED_OTHER) where it may;
// returns how many threads it could not move (EPERM without CAP_SYS_NICE or a suitable
// RLIMIT_NICE). For a process about to end with std::_Exit after letting an idle-priority worker
// go: the kernel ends a process only once each of its threads has run to take its exit, and a
// SCHED_IDLE thread on a machine other processes keep busy waited 20-30 s for that (measured
// with two `yes` beside the fake cell), while the process stayed unreaped.
int restore_normal_priority_of_all_threads();

// "normal" / "idle", as config files and command lines spell them; nullopt for another name.
std::optional<WorkerPriority> worker_priority_from_name(const std::string& name);

class BackgroundWorker {
 public:
  explicit BackgroundWorker(WorkerPriority priority = WorkerPriority::kNormal);
  ~BackgroundWorker();  // finishes the queued tasks, then joins (unless let go)
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

  // Drops the tasks not yet started and waits up to `timeout` for the running one to end.
  // Returns true when the thread is idle; otherwise the thread is let go (detached): it finishes
  // its task on its own and the destructor does not wait for it. For an idle-priority worker
  // that another process starves: its task (told to stop) may get no CPU to see that for
  // minutes. A task let go must own everything it touches; a process that let one go should
  // end with std::_Exit rather than run static destructors under it.
  bool finish_or_let_go(std::chrono::milliseconds timeout);

 private:
  struct State {
    std::mutex mutex;
    std::condition_variable wake, idle;
    std::deque<std::function<void()>> jobs;
    bool stopping = false, running = false;
  };
  void enqueue(std::function<void()> job);
  static void run(std::shared_ptr<State> state, WorkerPriority priority, std::promise<std::string> priority_set);

  std::shared_ptr<State> state_ = std::make_shared<State>();
  std::shared_future<std::string> priority_problem_;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace cell
