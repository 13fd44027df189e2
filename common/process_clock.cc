#include "common/process_clock.h"

#include <atomic>
#include <chrono>
#include <stdexcept>

namespace prepreg {
namespace {

std::atomic<bool> g_active{false};
std::atomic<std::int64_t> g_utime{0};

template <class Clock>
std::int64_t microseconds_of() {
  return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
}

}  // namespace

std::int64_t process_steady_us() {
  return g_active.load(std::memory_order_acquire) ? g_utime.load() : microseconds_of<std::chrono::steady_clock>();
}

std::int64_t process_epoch_us() {
  return g_active.load(std::memory_order_acquire) ? g_utime.load() : microseconds_of<std::chrono::system_clock>();
}

bool simulated_time_active() { return g_active.load(); }

SimulatedTime::SimulatedTime() {
  g_utime = 0;
  bool expected = false;
  if (!g_active.compare_exchange_strong(expected, true)) {
    throw std::logic_error("a SimulatedTime is already alive in this process (one clock per process)");
  }
}

SimulatedTime::~SimulatedTime() {
  g_active = false;
  g_utime = 0;
}

void SimulatedTime::set_us(std::int64_t utime) {
  std::int64_t current = g_utime.load();
  while (utime > current && !g_utime.compare_exchange_weak(current, utime)) {
  }
}

std::int64_t SimulatedTime::now_us() const { return g_utime.load(); }

}  // namespace prepreg
