// Cooperative cancellation (twin/base/cancellation.h): a set flag stops Newton at its next
// iteration, on the thread that installed it and on the lanes it starts; no flag, no effect.
#include <omp.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <mutex>
#include <vector>

#include "twin/base/cancellation.h"
#include "twin/base/job_lanes.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace {

// A 0.4 x 0.3 m sheet held at two corners, from flat: a solve of some tens of Newton iterations.
twin::SolveReport hang(int* iterations = nullptr) {
  const twin::SheetMesh mesh = twin::make_rectangular_sheet(0.4, 0.3, 0.05);
  const twin::ShellModel model(mesh, twin::Material{});
  const twin::ClampSet clamps(mesh, {{"A", {0.02, 0.02}, 0.0}, {"B", {0.38, 0.02}, 0.0}});
  std::vector<twin::ClampPose> poses(2);
  poses[0].position_m = {0.05, 0.02, 1.0};
  poses[1].position_m = {0.35, 0.02, 1.0};
  twin::SheetPlacement flat;
  flat.origin_m = {0.0, 0.0, 1.0};
  twin::VecX x = twin::place_flat(mesh, flat);
  twin::StaticSolver solver(model);
  const twin::SolveReport r = solver.solve(clamps, poses, x, twin::default_static_options(),
                                           twin::StaticSolver::OnFailure::kGiveUp);
  if (iterations) *iterations = r.iterations;
  return r;
}

}  // namespace

TEST_CASE("a set cancellation flag stops Newton at once, an unset or absent one changes nothing", "[cancellation]") {
  int free_iterations = 0;
  REQUIRE(hang(&free_iterations).usable());
  REQUIRE(free_iterations > 2);

  std::atomic<bool> flag{false};
  {
    const twin::CancellationScope scope(&flag);
    CHECK(hang().usable());  // installed, not set
    flag = true;
    CHECK(twin::cancellation_requested());
    const twin::SolveReport r = hang();
    CHECK(r.status == twin::SolveStatus::kCancelled);
    CHECK(r.iterations == 0);
    CHECK_FALSE(r.usable());
  }
  CHECK_FALSE(twin::cancellation_requested());  // the scope restored "none"
  CHECK(hang().usable());
}

TEST_CASE("the lanes a cancelled thread starts see its flag", "[cancellation]") {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  std::atomic<bool> flag{true};
  std::mutex mutex;
  std::vector<bool> seen;
  {
    const twin::CancellationScope scope(&flag);
    twin::JobQueue queue;
    for (int k = 0; k < 4; ++k) {
      queue.push([&](int) {
        std::lock_guard<std::mutex> lock(mutex);
        seen.push_back(twin::cancellation_requested());
      });
    }
    twin::run_lanes(2, queue, [] {});
  }
  omp_set_num_threads(saved);
  REQUIRE(seen.size() == 4);
  for (bool s : seen) CHECK(s);
}
