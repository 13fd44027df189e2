// The lanes that run a trial's fresh solves side by side (twin/base/job_lanes.h).
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "twin/base/job_lanes.h"

namespace {

// Restores OpenMP's thread count when a test has changed it.
struct ThreadCount {
  int saved = omp_get_max_threads();
  explicit ThreadCount(int n) { omp_set_num_threads(n); }
  ~ThreadCount() { omp_set_num_threads(saved); }
};

}  // namespace

TEST_CASE("every job runs once, including those the lead adds while it runs", "[job_lanes]") {
  ThreadCount two(2);
  twin::JobQueue queue;
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<int> ran;
  std::set<int> lanes_used;
  const auto job = [&](int id) {
    return [&, id](int lane) {
      std::lock_guard<std::mutex> lock(mutex);
      ran.push_back(id);
      lanes_used.insert(lane);
      changed.notify_all();
    };
  };
  for (int id = 0; id < 4; ++id) queue.push(job(id));
  twin::run_lanes(2, queue, [&] {
    // The lead holds lane 0 until lane 1 has run a queued job: that is what is tested, and a
    // lane 1 that never ran one while the lead ran is the failure. How soon it does depends on
    // when its thread gets a core, so the lead waits for it rather than for a time; 60 s only
    // keeps a broken run_lanes from hanging the test.
    {
      std::unique_lock<std::mutex> lock(mutex);
      changed.wait_for(lock, std::chrono::seconds(60), [&] { return lanes_used.count(1) == 1; });
    }
    for (int id = 4; id < 8; ++id) queue.push(job(id));
  });
  std::sort(ran.begin(), ran.end());
  CHECK(ran == std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7});
  // The queued jobs could start at once, while lane 0 was still busy with the lead.
  CHECK(lanes_used.count(1) == 1);
}

TEST_CASE("one lane runs the lead first, then the jobs in order", "[job_lanes]") {
  ThreadCount one(1);
  CHECK(twin::available_lanes(2) == 1);
  twin::JobQueue queue;
  std::vector<int> order;  // one lane: no lock needed
  queue.push([&](int lane) {
    CHECK(lane == 0);
    order.push_back(1);
  });
  twin::run_lanes(2, queue, [&] {
    order.push_back(0);
    queue.push([&](int) { order.push_back(2); });
  });
  CHECK(order == std::vector<int>{0, 1, 2});
}

TEST_CASE("inside an active parallel region there is one lane and jobs nest inactive", "[job_lanes]") {
  ThreadCount two(2);
  std::atomic<int> lanes{0}, inner_threads{0};
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    {
      lanes = twin::available_lanes(2);
      twin::JobQueue queue;
      queue.push([&](int) {
#pragma omp parallel num_threads(2)
        {
#pragma omp single
          inner_threads = omp_get_num_threads();
        }
      });
      twin::run_lanes(2, queue, [] {});
    }
  }
  CHECK(lanes == 1);
  CHECK(inner_threads == 1);
}

TEST_CASE("a job's parallel loop runs on the job's own thread", "[job_lanes]") {
  ThreadCount two(2);
  twin::JobQueue queue;
  std::atomic<int> widest{0};
  for (int k = 0; k < 4; ++k) {
    queue.push([&](int) {
#pragma omp parallel
      {
        const int n = omp_get_num_threads();
        int seen = widest.load();
        while (n > seen && !widest.compare_exchange_weak(seen, n)) {
        }
      }
    });
  }
  twin::run_lanes(2, queue, [] {});
  CHECK(widest == 1);
}

TEST_CASE("the first exception is rethrown after the lanes stop, and later jobs are dropped",
          "[job_lanes]") {
  for (const int threads : {1, 2}) {
    ThreadCount count(threads);
    twin::JobQueue queue;
    std::atomic<int> after{0};
    // With two lanes the lead pushes its job once lane 1 has thrown (waiting for that, not for a
    // time), plus 50 ms for lane 1 to record the exception: only a lane 1 stopped for longer
    // between its throw and its catch could let lane 0 run the job. With one lane the lead
    // runs first and the failing job after it, in order.
    std::atomic<bool> thrown{false};
    queue.push([&](int) {
      thrown = true;
      throw std::runtime_error("job failed");
    });
    CHECK_THROWS_WITH(twin::run_lanes(2, queue,
                                      [&] {
                                        if (threads == 2) {
                                          for (int i = 0; i < 60000 && !thrown; ++i) {
                                            std::this_thread::sleep_for(std::chrono::milliseconds(1));
                                          }
                                          std::this_thread::sleep_for(std::chrono::milliseconds(50));
                                        }
                                        queue.push([&](int) { ++after; });
                                      }),
                      "job failed");
    CHECK(after == 0);
    // A failing lead: the queue still closes and the lanes stop.
    twin::JobQueue second;
    second.push([](int) {});
    CHECK_THROWS_WITH(twin::run_lanes(2, second, [] { throw std::runtime_error("lead failed"); }),
                      "lead failed");
  }
}
