#include "sim_hw/spline_shell/branch_label.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

namespace sim_hw::spline_shell {
namespace {

// The signed principal curvature of largest magnitude (1/m) at a material point: the shape
// operator I^-1 II from the first and second fundamental forms.
double dominant_curvature_1_m(const SplinePatch& patch, const VecX& x, const Vec2& uv) {
  const PointWeights pw = patch.weights_at(uv);
  Vec3 d[6];
  for (Vec3& v : d) v.setZero();
  for (std::size_t k = 0; k < pw.controls.size(); ++k) {
    for (int r = 0; r < 6; ++r) d[r] += pw.w(r, k) * x.segment<3>(3 * pw.controls[k]);
  }
  const Vec3 n = d[kU].cross(d[kV]).normalized();
  Eigen::Matrix2d I, II;
  I << d[kU].dot(d[kU]), d[kU].dot(d[kV]), d[kU].dot(d[kV]), d[kV].dot(d[kV]);
  II << d[kUU].dot(n), d[kUV].dot(n), d[kUV].dot(n), d[kVV].dot(n);
  const Eigen::Vector2cd k = (I.inverse() * II).eigenvalues();  // real: I, II symmetric, I positive definite
  return std::abs(k[0].real()) >= std::abs(k[1].real()) ? k[0].real() : k[1].real();
}

}  // namespace

std::string BranchLabel::text() const {
  if (folds.empty()) return "no fold";
  std::string s = fmt::format("{} fold{}:", folds.size(), folds.size() == 1 ? "" : "s");
  for (std::size_t i = 0; i < folds.size(); ++i) {
    const Fold& f = folds[i];
    s += fmt::format("{} {}({:.0f}, {:.0f}) mm {:.0f} cm^2", i ? "," : "", f.sign > 0 ? '+' : '-', 1e3 * f.centre_m.x(),
                     1e3 * f.centre_m.y(), 1e4 * f.area_m2);
  }
  return s;
}

BranchLabel branch_label(const SplinePatch& patch, const VecX& x, const FoldOptions& options) {
  const int nu = std::max(2, static_cast<int>(std::round(patch.width_m() / options.sample_m)));
  const int nv = std::max(2, static_cast<int>(std::round(patch.height_m() / options.sample_m)));
  const double du = patch.width_m() / nu, dv = patch.height_m() / nv;
  // Cell centres of an nu x nv grid over the material sheet.
  std::vector<double> kappa(static_cast<std::size_t>(nu) * nv);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) kappa[j * nu + i] = dominant_curvature_1_m(patch, x, Vec2((i + 0.5) * du, (j + 0.5) * dv));
  }
  const double core = 1.0 / options.fold_radius_m, rim = 0.5 * core;
  std::vector<char> taken(kappa.size(), 0);
  std::vector<int> stack;
  // The region of one sign tighter than the rim that holds `start`, its cells marked taken.
  const auto grow = [&](int start) {
    Fold fold;
    fold.sign = kappa[start] > 0 ? 1 : -1;
    Vec2 sum = Vec2::Zero();
    stack.assign(1, start);
    taken[start] = 1;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      const int i = c % nu, j = c / nu;
      fold.cells_m.push_back(Vec2((i + 0.5) * du, (j + 0.5) * dv));
      sum += fold.cells_m.back();
      fold.peak_curvature_1_m = std::max(fold.peak_curvature_1_m, std::abs(kappa[c]));
      const int neighbours[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
      for (const auto& nb : neighbours) {
        if (nb[0] < 0 || nb[0] >= nu || nb[1] < 0 || nb[1] >= nv) continue;
        const int m = nb[1] * nu + nb[0];
        if (!taken[m] && fold.sign * kappa[m] >= rim) {
          taken[m] = 1;
          stack.push_back(m);
        }
      }
    }
    fold.area_m2 = static_cast<double>(fold.cells_m.size()) * du * dv;
    fold.centre_m = sum / static_cast<double>(fold.cells_m.size());
    return fold;
  };
  BranchLabel label;
  // Folds first (grown from their cores), then what is left tighter than the rim: bends.
  for (int start = 0; start < static_cast<int>(kappa.size()); ++start) {
    if (taken[start] || std::abs(kappa[start]) < core) continue;
    Fold fold = grow(start);
    if (fold.area_m2 >= options.least_area_m2) label.folds.push_back(std::move(fold));
  }
  for (int start = 0; start < static_cast<int>(kappa.size()); ++start) {
    if (taken[start] || std::abs(kappa[start]) < rim) continue;
    Fold bend = grow(start);
    if (bend.area_m2 >= options.least_area_m2) label.bends.push_back(std::move(bend));
  }
  std::sort(label.folds.begin(), label.folds.end(), [](const Fold& a, const Fold& b) { return a.area_m2 > b.area_m2; });
  return label;
}

bool same_branch(const BranchLabel& a, const BranchLabel& b, double tolerance_m, double significant_area_m2,
                 std::string* why) {
  // Every significant fold of one label must lie, for at least half its cells, within
  // tolerance_m of cells of same-signed folds or bends in the other: a fold that splits in two,
  // merges, shrinks or sharpens out of a bend between levels is still there, a flap turned over
  // or a fold gone is not.
  const auto covered = [&](const Fold& f, const BranchLabel& in) {
    std::vector<const Fold*> regions;
    for (const auto* list : {&in.folds, &in.bends}) {
      for (const Fold& g : *list) regions.push_back(&g);
    }
    int near = 0;
    for (const Vec2& p : f.cells_m) {
      bool found = false;
      for (const Fold* gp : regions) {
        const Fold& g = *gp;
        if (g.sign != f.sign) continue;
        for (const Vec2& q : g.cells_m) {
          if ((q - p).squaredNorm() <= tolerance_m * tolerance_m) {
            found = true;
            break;
          }
        }
        if (found) break;
      }
      near += found;
    }
    return 2 * near >= static_cast<int>(f.cells_m.size());
  };
  for (const auto& [from, in] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    for (const Fold& f : from->folds) {
      if (f.area_m2 < significant_area_m2 || covered(f, *in)) continue;
      if (why) {
        *why = fmt::format("the {}fold at ({:.0f}, {:.0f}) mm, {:.0f} cm^2, has no match within {:.0f} mm",
                           f.sign > 0 ? "+" : "-", 1e3 * f.centre_m.x(), 1e3 * f.centre_m.y(), 1e4 * f.area_m2,
                           1e3 * tolerance_m);
      }
      return false;
    }
  }
  return true;
}

}  // namespace sim_hw::spline_shell
