#pragma once
// Wall-clock seconds a learning job has run, for its report (never to decide anything).
#include <chrono>

namespace cell::learning {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace cell::learning
