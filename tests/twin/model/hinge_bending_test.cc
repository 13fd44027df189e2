#include "twin/model/hinge_bending.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "tests/support/finite_difference.h"
#include "tests/support/random_states.h"
#include "twin/model/dihedral_angle.h"

namespace twin {
namespace {

using testing::finite_difference_errors;

std::vector<Vec2> random_hinge_rest(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  // x0, x1 on the hinge, x2 on one side (triangle A ccw), x3 on the other.
  return {Vec2(0, 0) + Vec2(u(rng), u(rng)), Vec2(0.1, 0) + Vec2(u(rng), u(rng)),
          Vec2(0.05, 0.08) + Vec2(u(rng), u(rng)), Vec2(0.05, -0.08) + Vec2(u(rng), u(rng))};
}

TEST_CASE("dihedral angle derivatives match finite differences", "[twin][energy]") {
  std::mt19937 rng(5);
  auto theta = [](const VecX& x, VecX* g, Eigen::MatrixXd* h) {
    Vec12 gh;
    Mat12 hh;
    const double t = dihedral_angle(x, g ? &gh : nullptr, h ? &hh : nullptr);
    if (g) *g = gh;
    if (h) *h = hh;
    return t;
  };
  for (int trial = 0; trial < 20; ++trial) {
    const VecX x = testing::random_deformed(random_hinge_rest(rng), 0.1, 0.3, rng);
    const auto errors = finite_difference_errors(theta, x, 1e-7);
    INFO(errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-6);
  }
}

TEST_CASE("dihedral angle is zero flat and has the documented sign", "[twin][energy]") {
  Vec12 x;
  x << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0;
  CHECK(dihedral_angle(x, nullptr, nullptr) == Approx(0.0).margin(1e-15));
  // Fold both wings up by 30 degrees each: theta = -60 degrees.
  const double a = M_PI / 6;
  x.segment<3>(6) = Vec3(0.5, std::cos(a), std::sin(a));
  x.segment<3>(9) = Vec3(0.5, -std::cos(a), std::sin(a));
  CHECK(dihedral_angle(x, nullptr, nullptr) == Approx(-M_PI / 3));
}

TEST_CASE("hinge bending derivatives match finite differences", "[twin][energy]") {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    HingeElement h;
    h.stiffness_Nm = 2e-3;
    h.rest_angle_rad = trial % 2 ? 0.0 : 0.3;
    const VecX x = testing::random_deformed(random_hinge_rest(rng), 0.1, 0.3, rng);
    auto energy = [&h](const VecX& y, VecX* g, Eigen::MatrixXd* hm) {
      Vec12 gh;
      Mat12 hh;
      const double e = hinge_bending_energy(h, y, g ? &gh : nullptr, hm ? &hh : nullptr,
                                            HessianMode::kExact);
      if (g) *g = gh;
      if (hm) *hm = hh;
      return e;
    };
    const auto errors = finite_difference_errors(energy, x, 1e-7);
    INFO(errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-6);
  }
}

TEST_CASE("hinges of a mesh are its interior edges, oriented by triangle A", "[twin][mesh]") {
  const SheetMesh mesh = make_rectangular_sheet(0.3, 0.2, 0.05);
  const auto hinges = build_hinges(mesh);
  int boundary_edges = 0;
  // Euler: interior edges = (3F - boundary edges) / 2.
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) count[std::minmax(t[k], t[(k + 1) % 3])]++;
  for (const auto& [edge, c] : count) boundary_edges += c == 1;
  CHECK(static_cast<int>(hinges.size()) == (3 * mesh.triangle_count() - boundary_edges) / 2);
  for (const Hinge& h : hinges) {
    const auto& ta = mesh.triangles[h.triangle_a];
    bool found = false;
    for (int k = 0; k < 3; ++k) found |= ta[k] == h.v[0] && ta[(k + 1) % 3] == h.v[1] && ta[(k + 2) % 3] == h.v[2];
    CHECK(found);
  }
}

}  // namespace
}  // namespace twin
