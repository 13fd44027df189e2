// Branch labels name a shape by its folds: a hairpin fold is found where it is, with its sign and
// area; the same fold on a finer patch is the same branch; the fold turned the other way, or
// moved by more than its width, is another; a fold a coarser level draws as a bend in its place
// is the same; a gently curved sheet has none.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "sim_hw/spline_shell/branch_label.h"
#include "shell_fixtures.h"

namespace ss = sim_hw::spline_shell;

namespace {

// A 0.2 x 0.1 m sheet, flat up to u = start_m, then bent through half a turn of radius_m about
// an axis along v (towards +z for side +1, -z for -1), then flat again, lying back over itself.
ss::VecX hairpin(const ss::SplinePatch& patch, double start_m, double radius_m, int side) {
  const double arc_m = M_PI * radius_m;
  return patch.interpolate([=](const ss::Vec2& uv) {
    const double u = uv.x();
    if (u <= start_m) return ss::Vec3(u, uv.y(), 0.0);
    if (u <= start_m + arc_m) {
      const double t = (u - start_m) / radius_m;
      return ss::Vec3(start_m + radius_m * std::sin(t), uv.y(), side * radius_m * (1 - std::cos(t)));
    }
    return ss::Vec3(start_m - (u - start_m - arc_m), uv.y(), side * 2 * radius_m);
  });
}

}  // namespace

TEST_CASE("spline shell: a hairpin fold is labelled where it is, with its sign and area", "[spline_shell][branch]") {
  const ss::SplinePatch patch = shell_fixtures::uniform_patch(3, 40, 20, 0.2, 0.1);
  const ss::BranchLabel label = ss::branch_label(patch, hairpin(patch, 0.06, 0.02, +1));
  INFO(label.text());
  REQUIRE(label.folds.size() == 1);
  const ss::Fold& fold = label.folds.front();
  CHECK(fold.sign == 1);
  CHECK(fold.centre_m.x() == Approx(0.06 + M_PI * 0.02 / 2).margin(0.004));
  CHECK(fold.centre_m.y() == Approx(0.05).margin(0.002));
  CHECK(fold.area_m2 == Approx(M_PI * 0.02 * 0.1).epsilon(0.15));
  CHECK(fold.peak_curvature_1_m == Approx(50).epsilon(0.1));
  CHECK(ss::branch_label(patch, hairpin(patch, 0.06, 0.02, -1)).folds.front().sign == -1);
}

TEST_CASE("spline shell: labels tell the same fold on a finer patch from a turned or moved one", "[spline_shell][branch]") {
  const ss::SplinePatch coarse = shell_fixtures::uniform_patch(3, 20, 10, 0.2, 0.1);
  const ss::SplinePatch fine = shell_fixtures::uniform_patch(3, 40, 20, 0.2, 0.1);
  const ss::BranchLabel a = ss::branch_label(coarse, hairpin(coarse, 0.06, 0.025, +1));
  const ss::BranchLabel b = ss::branch_label(fine, hairpin(fine, 0.06, 0.025, +1));
  INFO(a.text() << " | " << b.text());
  CHECK(ss::same_branch(a, b, 0.01));
  std::string why;
  CHECK_FALSE(ss::same_branch(a, ss::branch_label(fine, hairpin(fine, 0.06, 0.025, -1)), 0.01, 1e-3, &why));
  CHECK(why.find("no match") != std::string::npos);
  // Moved by more than its width (8 cm): another branch; by a centimetre: the same fold.
  const ss::BranchLabel narrow = ss::branch_label(fine, hairpin(fine, 0.03, 0.012, +1));
  CHECK_FALSE(ss::same_branch(narrow, ss::branch_label(fine, hairpin(fine, 0.12, 0.012, +1)), 0.01));
  CHECK(ss::same_branch(narrow, ss::branch_label(fine, hairpin(fine, 0.04, 0.012, +1)), 0.01));
  // A sheet rolled on a 10 cm cylinder bends, but folds nowhere.
  const ss::VecX rolled = fine.interpolate([](const ss::Vec2& uv) {
    return ss::Vec3(0.1 * std::sin(uv.x() / 0.1), uv.y(), 0.1 * (1 - std::cos(uv.x() / 0.1)));
  });
  const ss::BranchLabel none = ss::branch_label(fine, rolled);
  CHECK(none.folds.empty());
  CHECK(none.text() == "no fold");
  CHECK_FALSE(ss::same_branch(none, b, 0.01, 1e-3, &why));
  CHECK(why.find("+fold at (") != std::string::npos);
  // A fold the coarser level draws as a bend (radius 4.5 cm: tighter than twice the fold radius,
  // not than it) is the same fold, sharpened; the bend turned the other way is not.
  const ss::BranchLabel bent = ss::branch_label(coarse, hairpin(coarse, 0.03, 0.045, +1));
  INFO(bent.text());
  CHECK(bent.folds.empty());
  REQUIRE(bent.bends.size() == 1);
  CHECK(bent.bends.front().sign == 1);
  CHECK(ss::same_branch(bent, b, 0.01));
  CHECK_FALSE(ss::same_branch(ss::branch_label(coarse, hairpin(coarse, 0.03, 0.045, -1)), b, 0.01));
  CHECK(none.bends.empty());  // 10 cm is no bend either
  // A fold smaller than the significant area may come and go between levels.
  ss::BranchLabel with_small = b;
  with_small.folds.push_back({-1, ss::Vec2(0.18, 0.02), 5e-4, 40.0, {ss::Vec2(0.18, 0.02)}});
  CHECK(ss::same_branch(with_small, b, 0.01, 1e-3));
  CHECK_FALSE(ss::same_branch(with_small, b, 0.01, 4e-4));
}
