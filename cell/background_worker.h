#pragma once
// One long-lived thread that runs submitted tasks in order, each returning a future. The cell
// runs the twin's step on it beside the tracker every cycle; a thread made per cycle would also
// make OpenMP set up its thread state anew 30 times a second.

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

namespace cell {

class BackgroundWorker {
 public:
  BackgroundWorker();
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

 private:
  void enqueue(std::function<void()> job);
  void run();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace cell
