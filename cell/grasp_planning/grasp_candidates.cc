#include "cell/grasp_planning/grasp_candidates.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "twin/mesh/material_point.h"

namespace cell {
namespace {

using twin::Vec2;
using twin::Vec3;

struct Box {
  Vec2 lo, hi;
};

Box material_box(const twin::SheetMesh& mesh) {
  Box b{mesh.rest_uv.front(), mesh.rest_uv.front()};
  for (const Vec2& p : mesh.rest_uv) {
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

// Cyclic distance between two ring indices.
int ring_distance(int a, int b, int m) {
  const int d = std::abs(a - b) % m;
  return std::min(d, m - d);
}

}  // namespace

std::vector<Vec2> ring_points(const twin::SheetMesh& mesh, double inset_m, double spacing_m) {
  const Box b = material_box(mesh);
  const Vec2 lo = b.lo + Vec2::Constant(inset_m), hi = b.hi - Vec2::Constant(inset_m);
  std::vector<Vec2> points;
  if (!(hi.x() > lo.x() && hi.y() > lo.y())) return points;
  const Vec2 corners[4] = {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
  for (int side = 0; side < 4; ++side) {
    const Vec2 a = corners[side], c = corners[(side + 1) % 4];
    const int segments = std::max(1, static_cast<int>(std::lround((c - a).norm() / spacing_m)));
    for (int k = 0; k < segments; ++k) {
      const Vec2 p = a + (c - a) * (static_cast<double>(k) / segments);
      if (twin::locate_material_point(mesh, p)) points.push_back(p);
    }
  }
  return points;
}

std::vector<GraspCandidate> generate_candidates(const twin::SheetMesh& mesh, int n,
                                                const GraspSearchOptions& search) {
  std::vector<GraspCandidate> out;
  std::mt19937 rng(search.seed);
  for (double inset : search.inset_m) {
    const std::vector<Vec2> ring = ring_points(mesh, inset, search.ring_spacing_m);
    const int m = static_cast<int>(ring.size());
    if (m < 2 * n) continue;  // too small a ring to keep grasps apart
    std::set<std::vector<int>> seen;
    std::vector<std::pair<std::vector<int>, std::string>> sets;
    auto add = [&](std::vector<int> idx, const std::string& kind) {
      std::sort(idx.begin(), idx.end());
      if (seen.insert(idx).second) sets.emplace_back(idx, kind);
    };
    if (n == 4) {
      // Corners are where ring_points starts each side.
      std::vector<int> corners;
      const Box b = material_box(mesh);
      const Vec2 lo = b.lo + Vec2::Constant(inset), hi = b.hi - Vec2::Constant(inset);
      for (const Vec2& c : {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())}) {
        for (int i = 0; i < m; ++i) {
          if ((ring[i] - c).norm() < 1e-9) corners.push_back(i);
        }
      }
      if (corners.size() == 4) add(corners, "corners");
    }
    for (int offset = 0; offset < (m + n - 1) / n; ++offset) {
      std::vector<int> idx;
      for (int k = 0; k < n; ++k) idx.push_back((offset + static_cast<int>(std::lround(k * double(m) / n))) % m);
      add(idx, "even");
    }
    std::uniform_int_distribution<int> pick(0, m - 1);
    for (int r = 0, tries = 0; r < search.random_candidates && tries < 100 * search.random_candidates + 100; ++tries) {
      std::vector<int> idx;
      while (static_cast<int>(idx.size()) < n) {
        const int i = pick(rng);
        bool apart = true;
        for (int j : idx) apart &= ring_distance(i, j, m) >= 2;
        if (apart) idx.push_back(i);
      }
      const std::size_t before = sets.size();
      add(idx, "random");
      if (sets.size() > before) ++r;
    }
    for (const auto& [idx, kind] : sets) {
      for (double slack : search.slack_factors) {
        GraspCandidate c;
        for (int i : idx) c.points_uv_m.push_back(ring[i]);
        c.inset_m = inset;
        c.slack = slack;
        c.kind = kind;
        out.push_back(std::move(c));
      }
    }
  }
  return out;
}

Vec3 flat_layout_position(const twin::SheetMesh& mesh, const GraspGoal& goal, const Vec2& uv) {
  const Box b = material_box(mesh);
  const Vec2 d = uv - 0.5 * (b.lo + b.hi);
  const double c = std::cos(goal.tool.yaw_rad), s = std::sin(goal.tool.yaw_rad);
  const Vec2 xy = goal.tool.centre_m + Vec2(c * d.x() - s * d.y(), s * d.x() + c * d.y());
  return Vec3(xy.x(), xy.y(), goal.hold_z_m);
}

std::vector<Vec3> hold_positions(const twin::SheetMesh& mesh, const GraspGoal& goal,
                                 const GraspCandidate& candidate) {
  std::vector<Vec3> flat;
  Vec3 centroid = Vec3::Zero();
  for (const Vec2& uv : candidate.points_uv_m) {
    flat.push_back(flat_layout_position(mesh, goal, uv));
    centroid += flat.back();
  }
  centroid /= static_cast<double>(flat.size());
  for (Vec3& p : flat) p = centroid + (1.0 - candidate.slack) * (p - centroid);
  return flat;
}

}  // namespace cell
