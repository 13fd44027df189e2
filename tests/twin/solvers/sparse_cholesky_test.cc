#include <catch2/catch.hpp>

#include <omp.h>

#include <vector>

#include "twin/solvers/sparse_cholesky.h"

namespace twin {
namespace {

// Upper triangle of the n x n matrix tridiag(-1, 2 + shift, -1): positive definite for
// shift > -2 + 2 cos(pi / (n + 1)), indefinite well below.
HessianPattern::Matrix tridiagonal(int n, double shift) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 2.0 + shift);
    if (i > 0) entries.emplace_back(i - 1, i, -1.0);
  }
  HessianPattern::Matrix upper(n, n);
  upper.setFromTriplets(entries.begin(), entries.end());
  return upper;
}

int team_size() {
  int size = 0;
#pragma omp parallel
  {
#pragma omp single
    size = omp_get_num_threads();
  }
  return size;
}

TEST_CASE("a factorisation solves the system and refuses an indefinite matrix", "[twin][solver]") {
  const HessianPattern::Matrix spd = tridiagonal(300, 0.01);
  SparseCholesky cholesky;
  cholesky.analyze(spd);
  REQUIRE(cholesky.factorize(spd));
  const VecX rhs = VecX::LinSpaced(300, -1.0, 2.0);
  const VecX solution = cholesky.solve(rhs);
  const VecX residual = spd.selfadjointView<Eigen::Upper>() * solution - rhs;
  CHECK(residual.norm() < 1e-10 * rhs.norm());
  CHECK_FALSE(cholesky.factorize(tridiagonal(300, -1.0)));
  // The shift makes the indefinite matrix definite again (2 - 1 + 1.5 on the diagonal).
  CHECK(cholesky.factorize(tridiagonal(300, -1.0), 1.5));
}

// CHOLMOD's loops are made serial with a limit on this thread's nesting, which must be put back
// as it was: the caller's own parallel loops (the element loops, the tracker) keep their threads.
TEST_CASE("a factorisation leaves the caller's OpenMP nesting limit and team size as they were",
          "[twin][solver]") {
  const int saved_levels = omp_get_max_active_levels();
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(2);
  const HessianPattern::Matrix spd = tridiagonal(200, 0.1);
  SparseCholesky cholesky;
  cholesky.analyze(spd);
  for (int levels : {1, 2}) {
    omp_set_max_active_levels(levels);
    REQUIRE(cholesky.factorize(spd));
    CHECK(omp_get_max_active_levels() == levels);
    CHECK(team_size() == 2);
  }
  // Two factorisations at once, one per thread of a team (as on the lanes of job_lanes.h).
  omp_set_max_active_levels(1);
  SparseCholesky other;
  other.analyze(spd);
  bool ok[2] = {false, false};
#pragma omp parallel num_threads(2)
  {
    const int t = omp_get_thread_num();
    ok[t] = (t == 0 ? cholesky : other).factorize(spd);
  }
  CHECK(ok[0]);
  CHECK(ok[1]);
  CHECK(omp_get_max_active_levels() == 1);
  omp_set_max_active_levels(saved_levels);
  omp_set_num_threads(saved_threads);
}

}  // namespace
}  // namespace twin
