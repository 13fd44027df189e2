#include <catch2/catch.hpp>

#include <sched.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "cell/background_worker.h"

namespace cell {
namespace {

TEST_CASE("the background worker runs tasks in order on one other thread", "[cell][worker]") {
  BackgroundWorker worker;
  std::vector<int> order;  // touched by the worker only, read after the last future
  std::vector<std::future<std::thread::id>> ran;
  for (int i = 0; i < 20; ++i) {
    ran.push_back(worker.submit([&order, i] {
      std::this_thread::sleep_for(std::chrono::microseconds(100 * (i % 3)));
      order.push_back(i);
      return std::this_thread::get_id();
    }));
  }
  const std::thread::id first = ran.front().get();
  CHECK(first != std::this_thread::get_id());
  for (std::size_t i = 1; i < ran.size(); ++i) CHECK(ran[i].get() == first);
  REQUIRE(order.size() == 20u);
  for (int i = 0; i < 20; ++i) CHECK(order[static_cast<std::size_t>(i)] == i);
}

TEST_CASE("a task's exception reaches its future and the worker goes on", "[cell][worker]") {
  BackgroundWorker worker;
  auto failing = worker.submit([]() -> int { throw std::runtime_error("step threw"); });
  auto next = worker.submit([] { return 7; });
  CHECK_THROWS_WITH(failing.get(), "step threw");
  CHECK(next.get() == 7);
}

TEST_CASE("destroying the worker finishes the tasks already queued", "[cell][worker]") {
  std::atomic<int> done{0};
  {
    BackgroundWorker worker;
    for (int i = 0; i < 5; ++i) {
      worker.submit([&done] {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        ++done;
      });
    }
  }
  CHECK(done == 5);
}

// The twin's worker gives way to the cycle's threads: its tasks run under SCHED_IDLE, the
// submitting thread and a normal worker under the default policy.
TEST_CASE("an idle-priority worker runs its tasks under SCHED_IDLE, a normal one does not", "[cell][worker]") {
  BackgroundWorker idle(WorkerPriority::kIdle);
  BackgroundWorker normal;
  const auto policy = [] { return sched_getscheduler(0); };
  CHECK(idle.priority_problem().empty());
  CHECK(normal.priority_problem().empty());
  CHECK(idle.submit(policy).get() == SCHED_IDLE);
  CHECK(normal.submit(policy).get() == SCHED_OTHER);
  CHECK(policy() == SCHED_OTHER);
}

// A cell that let an idle-priority worker go puts its threads back at the normal policy before it
// ends, so that the kernel can end them at once on a busy machine.
TEST_CASE("restoring the normal priority moves an idle-priority worker's thread back to SCHED_OTHER",
          "[cell][worker]") {
  BackgroundWorker idle(WorkerPriority::kIdle);
  const auto policy = [] { return sched_getscheduler(0); };
  REQUIRE(idle.priority_problem().empty());
  REQUIRE(idle.submit(policy).get() == SCHED_IDLE);
  const int refused = restore_normal_priority_of_all_threads();
  // Leaving SCHED_IDLE needs CAP_SYS_NICE or an RLIMIT_NICE that allows nice 0: where it was
  // refused, the worker must still be as it was.
  CHECK(idle.submit(policy).get() == (refused == 0 ? SCHED_OTHER : SCHED_IDLE));
  CHECK(policy() == SCHED_OTHER);
}

// A stopping cell does not wait for a starved background task: it lets the worker go, the task
// ends on its own later, and nothing it owns is freed under it.
TEST_CASE("finish_or_let_go waits for an idle worker, lets a busy one go and drops what has not started",
          "[cell][worker]") {
  {
    BackgroundWorker w;
    CHECK(w.submit([] { return 1; }).get() == 1);
    // The worker is idle or about to be (it marks itself so after its task): the wait ends at
    // once. 60 s only keeps a broken worker from hanging the test.
    CHECK(w.finish_or_let_go(std::chrono::seconds(60)));
  }
  // The first task runs until released and says when it has started and when it has finished,
  // so nothing below depends on how soon a thread gets the CPU.
  auto release = std::make_shared<std::atomic<bool>>(false);
  auto started = std::make_shared<std::promise<void>>();
  auto finished = std::make_shared<std::promise<void>>();
  std::future<void> has_started = started->get_future(), has_finished = finished->get_future();
  std::future<int> second;
  {
    BackgroundWorker w;
    std::future<void> first = w.submit([release, started, finished] {
      started->set_value();
      while (!release->load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      finished->set_value();
    });
    second = w.submit([] { return 2; });
    // The first task runs; the second waits its turn. (60 s: only so that a broken worker fails
    // the test rather than hangs it; here and below no time is asserted.)
    REQUIRE(has_started.wait_for(std::chrono::seconds(60)) == std::future_status::ready);
    // The running task cannot end before it is released: this waits the full 50 ms, then lets go.
    CHECK_FALSE(w.finish_or_let_go(std::chrono::milliseconds(50)));
  }  // the destructor does not wait for the task let go
  CHECK(has_finished.wait_for(std::chrono::seconds(0)) == std::future_status::timeout);
  CHECK_THROWS_AS(second.get(), std::future_error);  // dropped, never run
  release->store(true);
  // The task let go still ends on its own.
  CHECK(has_finished.wait_for(std::chrono::seconds(60)) == std::future_status::ready);
}

}  // namespace
}  // namespace cell
