// A factorisation's analysis must leave the process's signal handlers alone: the cell and the
// fake world analyse on worker threads while the main thread waits for SIGTERM, and a handler
// swapped in by the ordering for the length of a call (METIS_NodeND's GKlib trap) runs on the
// main thread when the signal comes, where it crashed the process (sparse_cholesky.cc).
#include <catch2/catch.hpp>

#include <signal.h>

#include <atomic>
#include <thread>
#include <vector>

#include "twin/solvers/sparse_cholesky.h"

namespace twin {
namespace {

// Upper triangle of the 5-point Laplacian of an n x n grid plus the identity: a 2D mesh's
// pattern, large enough that its nested-dissection ordering takes milliseconds.
HessianPattern::Matrix grid_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> entries;
  auto index = [n](int i, int j) { return i * n + j; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      entries.emplace_back(index(i, j), index(i, j), 5.0);
      if (i > 0) entries.emplace_back(index(i - 1, j), index(i, j), -1.0);
      if (j > 0) entries.emplace_back(index(i, j - 1), index(i, j), -1.0);
    }
  }
  HessianPattern::Matrix upper(n * n, n * n);
  upper.setFromTriplets(entries.begin(), entries.end());
  return upper;
}

void marker_handler(int) {}

TEST_CASE("analysing a factorisation on another thread leaves the SIGTERM and SIGABRT handlers alone",
          "[twin][solver]") {
  struct sigaction marker {}, saved_term{}, saved_abort{};
  marker.sa_handler = marker_handler;
  sigemptyset(&marker.sa_mask);
  REQUIRE(sigaction(SIGTERM, &marker, &saved_term) == 0);
  REQUIRE(sigaction(SIGABRT, &marker, &saved_abort) == 0);

  const HessianPattern::Matrix upper = grid_laplacian(120);
  std::atomic<bool> done{false};
  bool factorised = true;
  std::thread worker([&] {
    for (int k = 0; k < 4; ++k) {
      SparseCholesky cholesky;  // a new one: each analyses afresh
      cholesky.analyze(upper);
      factorised = factorised && cholesky.factorize(upper);
    }
    done = true;
  });
  // Watch the handlers for as long as the worker analyses (each look is one system call).
  long looks = 0, swapped = 0;
  while (!done) {
    struct sigaction term {}, abort_action{};
    sigaction(SIGTERM, nullptr, &term);
    sigaction(SIGABRT, nullptr, &abort_action);
    swapped += term.sa_handler != marker_handler || abort_action.sa_handler != marker_handler;
    ++looks;
  }
  worker.join();
  sigaction(SIGTERM, &saved_term, nullptr);
  sigaction(SIGABRT, &saved_abort, nullptr);

  CHECK(factorised);
  INFO(looks << " looks at the handlers while the worker analysed, " << swapped << " saw another handler");
  CHECK(looks > 0);
  CHECK(swapped == 0);
}

}  // namespace
}  // namespace twin
