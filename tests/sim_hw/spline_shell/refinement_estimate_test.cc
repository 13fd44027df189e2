// The finest level's error from a stage's levels: an observed order and Richardson's estimate
// where the two finest comparisons are on one branch, nothing where they are not, and only the
// counted markers in the means.

#include <catch2/catch.hpp>

#include "sim_hw/spline_shell/refinement_estimate.h"

namespace ss = sim_hw::spline_shell;

namespace {

// Three markers per level: marker 0 moves by the level's change along x, marker 1 not at all,
// marker 2 (hidden under a jaw, not counted) by a metre.
std::vector<std::vector<ss::Vec3>> levels_with_changes(const std::vector<double>& changes_m) {
  std::vector<std::vector<ss::Vec3>> levels;
  ss::Vec3 moving(0.1, 0.2, 0.3);
  for (std::size_t l = 0; l <= changes_m.size(); ++l) {
    levels.push_back({moving, ss::Vec3(0.5, 0.5, 0.5), ss::Vec3(static_cast<double>(l), 0, 0)});
    if (l < changes_m.size()) moving.x() += changes_m[l];
  }
  return levels;
}

ss::BranchLabel one_fold(int sign) {
  ss::Fold f;
  f.sign = sign;
  f.centre_m = ss::Vec2(0.3, 0.3);
  f.area_m2 = 0.003;
  for (int i = 0; i < 10; ++i) f.cells_m.push_back(ss::Vec2(0.3 + 0.005 * i, 0.3));
  ss::BranchLabel label;
  label.folds.push_back(f);
  return label;
}

}  // namespace

TEST_CASE("refinement estimate: second order changes give order 2 and a third of the last change",
          "[spline_shell][estimate]") {
  const std::vector<bool> counted = {true, true, false};
  const std::vector<ss::BranchLabel> labels(3, one_fold(+1));
  const ss::StageRefinement r = ss::stage_refinement(levels_with_changes({0.004, 0.001}), labels, counted);
  REQUIRE(r.changes.size() == 2);
  // Means over the two counted markers: the hidden one's metre does not enter.
  CHECK(r.changes[0].mean_m == Approx(0.002));
  CHECK(r.changes[1].mean_m == Approx(0.0005));
  CHECK(r.finest().max_m == Approx(0.001));
  CHECK(r.finest().max_marker == 0);  // the moving one, not the hidden one's metre
  REQUIRE(r.estimated());
  CHECK(*r.order == Approx(2.0));
  CHECK(*r.finest_error_m == Approx(0.0005 / 3.0));
  CHECK(ss::estimate_text(r) == "order 2.00, finest error 0.167 mm (GCI 0.208)");
  CHECK(ss::change_text(1, r.finest()) == "1->2 0.500 / 1.000 mm");
  CHECK(ss::summary_text(r) ==
        "0->1 2.000 / 4.000 mm  1->2 0.500 / 1.000 mm  | order 2.00, finest error 0.167 mm (GCI 0.208)");
}

TEST_CASE("refinement estimate: no order from a branch flip, from two levels or from growing changes",
          "[spline_shell][estimate]") {
  const std::vector<bool> counted = {true, true, false};
  SECTION("the finest level turned its fold over") {
    const std::vector<ss::BranchLabel> labels = {one_fold(+1), one_fold(+1), one_fold(-1)};
    const ss::StageRefinement r = ss::stage_refinement(levels_with_changes({0.004, 0.001}), labels, counted);
    CHECK_FALSE(r.estimated());
    CHECK_FALSE(r.finest().same_branch);
    CHECK(r.no_order == "the two finest comparisons are not on one branch");
    CHECK(ss::change_text(1, r.finest()).find("BRANCH FLIP") != std::string::npos);
  }
  SECTION("two levels") {
    const ss::StageRefinement r = ss::stage_refinement(levels_with_changes({0.004}), {one_fold(+1), one_fold(+1)}, counted);
    CHECK_FALSE(r.estimated());
    CHECK(r.changes.size() == 1);
    CHECK(r.no_order == "one change only");
  }
  SECTION("the change grows with refinement") {
    const std::vector<ss::BranchLabel> labels(3, one_fold(+1));
    const ss::StageRefinement r = ss::stage_refinement(levels_with_changes({0.001, 0.002}), labels, counted);
    CHECK_FALSE(r.estimated());
    CHECK(r.no_order.find("below 0.2") != std::string::npos);
  }
  CHECK_THROWS_AS(ss::stage_refinement(levels_with_changes({0.004}), {one_fold(+1)}, counted), std::invalid_argument);
  CHECK_THROWS_AS(ss::stage_refinement(levels_with_changes({0.004}), {one_fold(+1), one_fold(+1)}, {true}),
                  std::invalid_argument);
}
