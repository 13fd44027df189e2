// Uniform-strain patch test of the membrane (linear triangles must reproduce any homogeneous
// deformation exactly). All vertices go to x = c + F X with X = (u, v) and F a constant 3 x 2
// deformation gradient; then, against continuum values computed here from F alone:
//   energy        = A * 1/2 eps^T C eps,  eps = ((|F_u|^2 - 1)/2, (|F_v|^2 - 1)/2, F_u . F_v)
//   interior      : zero net force
//   edge u = W    : sum of the gradient (the force the surroundings must apply to hold the
//                   edge; the membrane's own force on it is the opposite) = P (1, 0)^T H,
// with P = F S the first Piola-Kirchhoff stress (N/m) and S = [[s_uu, s_uv], [s_uv, s_vv]] the
// second, s = C eps. Edge v = H likewise: P (0, 1)^T W.

#include <catch2/catch.hpp>

#include "twin/model/material.h"
#include "twin/model/membrane_term.h"

namespace twin::patch_test {
namespace {

Material anisotropic_material() {
  Material m;
  m.tensile_stiffness_u_N_m = 5000.0;
  m.tensile_stiffness_v_N_m = 2000.0;
  m.shear_stiffness_N_m = 700.0;
  m.poisson_ratio = 0.3;
  return m;
}

// Length of the boundary segment of edge v = v_edge that ends at the corner u = width.
double corner_segment_m(const SheetMesh& mesh, double width_m, double v_edge_m) {
  double last = 0.0;
  for (const Vec2& p : mesh.rest_uv) {
    if (std::abs(p.y() - v_edge_m) < 1e-12 && p.x() < width_m - 1e-12) last = std::max(last, p.x());
  }
  return width_m - last;
}

TEST_CASE("membrane passes the uniform-strain patch test", "[twin][physics]") {
  const double width_m = 0.4, height_m = 0.28, edge_m = 0.05;  // 8 offset rows
  const Mat3 c = anisotropic_material().membrane_stiffness();
  // Stretch 1.02 along u, 0.99 along v, shear 0.01, then tilted out of the plane.
  Eigen::Matrix<double, 3, 2> f0;
  f0 << 1.02, 0.01, 0.0, 0.99, 0.0, 0.0;
  const Mat3 tilt =
      Eigen::AngleAxisd(0.6, Vec3(0.3, -1.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix<double, 3, 2> f = tilt * f0;
  const Vec3 origin(0.2, -0.7, 1.3);

  const Vec3 u = f.col(0), v = f.col(1);
  const Vec3 eps(0.5 * (u.squaredNorm() - 1.0), 0.5 * (v.squaredNorm() - 1.0), u.dot(v));
  REQUIRE(eps(0) == Approx(0.0202));  // the intended strain state, by hand
  REQUIRE(eps(1) == Approx(-0.0099));
  REQUIRE(eps(2) == Approx(0.0102));
  const Vec3 s = c * eps;  // N/m
  Mat2 second_pk;
  second_pk << s(0), s(2), s(2), s(1);
  const Eigen::Matrix<double, 3, 2> first_pk = f * second_pk;  // N/m
  const Vec3 traction_u_N = first_pk.col(0) * height_m;
  const Vec3 traction_v_N = first_pk.col(1) * width_m;
  const double energy_J = width_m * height_m * 0.5 * eps.dot(c * eps);

  for (auto pattern : {TriangulationPattern::kOffsetRows, TriangulationPattern::kRightTriangles}) {
    INFO("pattern " << static_cast<int>(pattern));
    const SheetMesh mesh = make_rectangular_sheet(width_m, height_m, edge_m, pattern);
    // The summed gradient on edge u = W is P times the boundary integral of the sum of that
    // edge's hat functions: H (1, 0) plus half the corner segments of the edges v = 0 and
    // v = H, which cancel only if they are equally long (an even number of offset rows).
    REQUIRE(corner_segment_m(mesh, width_m, 0.0) ==
            Approx(corner_segment_m(mesh, width_m, height_m)).epsilon(1e-12));
    const MembraneTerm membrane(mesh, c);
    const int n = mesh.vertex_count();
    VecX x(3 * n);
    for (int i = 0; i < n; ++i) vertex(x, i) = origin + f * mesh.rest_uv[i];

    VecX grad = VecX::Zero(3 * n);
    const double energy = membrane.evaluate(x, &grad, nullptr, HessianMode::kExact);
    CHECK(energy == Approx(energy_J).epsilon(1e-10));

    Vec3 edge_u = Vec3::Zero(), edge_v = Vec3::Zero(), total = Vec3::Zero();
    double largest_interior = 0.0, largest_boundary = 0.0;
    int on_edge_u = 0;
    for (int i = 0; i < n; ++i) {
      const Vec2& p = mesh.rest_uv[i];
      const Vec3 g = vertex(grad, i);
      total += g;
      const bool at_u = std::abs(p.x() - width_m) < 1e-12;
      const bool at_v = std::abs(p.y() - height_m) < 1e-12;
      const bool boundary = at_u || at_v || p.x() < 1e-12 || p.y() < 1e-12;
      if (at_u) {
        ++on_edge_u;
        edge_u += g;
      }
      if (at_v) edge_v += g;
      double& largest = boundary ? largest_boundary : largest_interior;
      largest = std::max(largest, g.norm());
    }
    REQUIRE(on_edge_u >= 7);
    REQUIRE(largest_boundary > 1.0);  // N
    CHECK(largest_interior <= 1e-9 * largest_boundary);
    CHECK((edge_u - traction_u_N).norm() <= 1e-9 * traction_u_N.norm());
    CHECK((edge_v - traction_v_N).norm() <= 1e-9 * traction_v_N.norm());
    CHECK(total.norm() <= 1e-9 * traction_u_N.norm());
  }
}

}  // namespace
}  // namespace twin::patch_test
