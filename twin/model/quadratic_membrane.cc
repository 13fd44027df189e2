#include "twin/model/quadratic_membrane.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "twin/model/membrane_point.h"

namespace twin {

QuadraticMembraneElement make_quadratic_membrane_element(const SheetMesh& mesh, int patch) {
  QuadraticMembraneElement e;
  e.v = mesh.quadratic_patches.at(static_cast<std::size_t>(patch));
  const Vec2& pa = mesh.rest_uv[e.v[0]];
  const Vec2& pb = mesh.rest_uv[e.v[1]];
  const Vec2& pc = mesh.rest_uv[e.v[2]];
  const double size_m = std::max({(pb - pa).norm(), (pc - pb).norm(), (pa - pc).norm()});
  const std::array<Vec2, 3> midpoints{0.5 * (pa + pb), 0.5 * (pb + pc), 0.5 * (pc + pa)};
  for (int k = 0; k < 3; ++k) {
    if ((mesh.rest_uv[e.v[3 + k]] - midpoints[k]).norm() > 1e-9 * size_m) {
      throw std::invalid_argument("quadratic patch " + std::to_string(patch) + ": vertex " +
                                  std::to_string(e.v[3 + k]) + " is not the midpoint of its edge");
    }
  }
  Mat2 edges;
  edges.col(0) = pb - pa;
  edges.col(1) = pc - pa;
  e.rest_area_m2 = 0.5 * edges.determinant();
  if (!(e.rest_area_m2 > 0.0)) {
    throw std::invalid_argument("quadratic patch " + std::to_string(patch) + ": corners not counter-clockwise");
  }
  // Gradients of the barycentric coordinates L_a, L_b, L_c (constant over the triangle).
  const Mat2 inv = edges.inverse();
  const std::array<Vec2, 3> g{Vec2(-inv.row(0).transpose() - inv.row(1).transpose()), Vec2(inv.row(0).transpose()),
                              Vec2(inv.row(1).transpose())};
  // The three-point rule: each point at 2/3 of one barycentric coordinate, 1/6 of the others.
  for (int q = 0; q < 3; ++q) {
    std::array<double, 3> l{1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0};
    l[static_cast<std::size_t>(q)] = 2.0 / 3.0;
    Eigen::Matrix<double, 6, 2>& r = e.r[static_cast<std::size_t>(q)];
    for (int k = 0; k < 3; ++k) {
      const int next = (k + 1) % 3;
      // Corner k: L_k (2 L_k - 1); midpoint of edge (k, k+1): 4 L_k L_{k+1}.
      r.row(k) = (4.0 * l[k] - 1.0) * g[k].transpose();
      r.row(3 + k) = 4.0 * (l[next] * g[k] + l[k] * g[next]).transpose();
    }
  }
  return e;
}

double quadratic_membrane_energy(const QuadraticMembraneElement& e, const Mat3& c, const Vec18& xe, Vec18* grad,
                                 Mat18* hess, HessianMode mode) {
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  double energy = 0.0;
  for (const auto& r : e.r) energy += add_membrane_point_energy<6>(r, e.rest_area_m2 / 3.0, c, xe, grad, hess, mode);
  return energy;
}

QuadraticMembraneTerm::QuadraticMembraneTerm(const SheetMesh& mesh, const Mat3& stiffness_N_m)
    : stiffness_(stiffness_N_m) {
  if (mesh.quadratic_patches.empty()) {
    throw std::invalid_argument(
        "the quadratic membrane needs a mesh refined uniformly from a coarser one (its quadratic patches); "
        "this mesh has none");
  }
  std::vector<int> vertices;
  vertices.reserve(6 * mesh.quadratic_patches.size());
  for (int p = 0; p < static_cast<int>(mesh.quadratic_patches.size()); ++p) {
    elements_.push_back(make_quadratic_membrane_element(mesh, p));
    vertices.insert(vertices.end(), elements_.back().v.begin(), elements_.back().v.end());
  }
  set_elements(std::move(vertices), mesh.vertex_count());
}

}  // namespace twin
