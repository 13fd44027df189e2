#include "twin/model/plate_bending_term.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "twin/model/dihedral_angle.h"
#include "twin/model/hinge_bending.h"

namespace twin {
namespace {

// A vertex of the mesh not among `used`, as close to `near` as the mesh's numbering allows:
// the stand-in for the missing neighbour of a free edge (its derivatives are zero, it only
// has to be a distinct vertex so the element's Hessian blocks are distinct).
int stand_in_vertex(int vertex_count, const std::array<int, 6>& used, int count, int near) {
  for (int offset = 1; offset < vertex_count; ++offset) {
    for (int candidate : {near + offset, near - offset}) {
      if (candidate < 0 || candidate >= vertex_count) continue;
      bool taken = false;
      for (int i = 0; i < count; ++i) taken |= used[i] == candidate;
      if (!taken) return candidate;
    }
  }
  throw std::invalid_argument("plate bending: the mesh needs at least 6 vertices");
}

void require_rigidity(const Mat3& d) {
  const bool orthotropic = d(0, 2) == 0.0 && d(1, 2) == 0.0 && d(2, 0) == 0.0 && d(2, 1) == 0.0 &&
                           d(0, 1) == d(1, 0);
  const bool finite = d.allFinite();
  if (!finite || !orthotropic || !(d(0, 0) > 0.0 && d(1, 1) > 0.0 && d(2, 2) > 0.0) ||
      !(d(0, 1) * d(0, 1) < d(0, 0) * d(1, 1))) {
    throw std::invalid_argument(
        "plate bending: the rigidity D must have D11, D22, D66 > 0 and D12^2 < D11 D22 (N*m), got "
        "D11 " + std::to_string(d(0, 0)) + ", D22 " + std::to_string(d(1, 1)) + ", D12 " +
        std::to_string(d(0, 1)) + ", D66 " + std::to_string(d(2, 2)));
  }
}

}  // namespace

Mat3 plate_rigidity_matrix(double d11_Nm, double d22_Nm, double d12_Nm, double d66_Nm) {
  Mat3 d = Mat3::Zero();
  d(0, 0) = d11_Nm;
  d(1, 1) = d22_Nm;
  d(0, 1) = d(1, 0) = d12_Nm;
  d(2, 2) = d66_Nm;
  return d;
}

PlateBendingTerm::PlateBendingTerm(const SheetMesh& mesh, const Mat3& rigidity_Nm) {
  require_rigidity(rigidity_Nm);
  // Directed edge (a -> b, counter-clockwise in its triangle) -> the third vertex.
  std::map<std::pair<int, int>, int> third;
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) third[{tri[(k + 1) % 3], tri[(k + 2) % 3]}] = tri[k];
  }
  std::vector<int> vertices;
  std::vector<Hinge> hinges;  // three per element (unused slots repeat the first)
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    PlateElement e;
    std::array<int, 3> opposite{-1, -1, -1};
    for (int k = 0; k < 3; ++k) {
      // The neighbour runs the edge the other way.
      auto it = third.find({tri[(k + 2) % 3], tri[(k + 1) % 3]});
      if (it != third.end()) {
        opposite[k] = it->second;
        e.edge[e.hinge_count++] = k;
      }
    }
    if (e.hinge_count == 0) continue;  // an isolated triangle cannot bend
    for (int k = 0; k < 3; ++k) e.v[k] = tri[k];
    for (int k = 0; k < 3; ++k) e.v[3 + k] = opposite[k];
    for (int k = 0; k < 3; ++k) {
      if (opposite[k] >= 0) continue;
      std::array<int, 6> taken{};
      int n = 0;
      for (int i = 0; i < 6; ++i) {
        if (e.v[i] >= 0) taken[n++] = e.v[i];
      }
      e.v[3 + k] = stand_in_vertex(mesh.vertex_count(), taken, n, tri[k]);
    }
    for (int j = 0; j < 3; ++j) {
      const int k = e.edge[j < e.hinge_count ? j : 0];
      Hinge h;
      const auto local = plate_hinge_local_vertices(k);
      for (int i = 0; i < 4; ++i) h.v[i] = e.v[local[i]];
      hinges.push_back(h);
    }
    elements_.push_back(e);
    area_m2_.push_back(mesh.rest_area(t));
    vertices.insert(vertices.end(), e.v.begin(), e.v.end());
  }
  const HingeCurvatureMap map(mesh, hinges);
  angle_per_curvature_.assign(elements_.size(), Mat3::Zero());
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    for (int j = 0; j < elements_[i].hinge_count; ++j) {
      const Vec3& a = map.coefficients(static_cast<int>(3 * i + j));  // per (uu, vv, uv)
      angle_per_curvature_[i].row(j) = Eigen::RowVector3d(a(0), a(1), 0.5 * a(2));
    }
  }
  curvature_per_angle_.assign(elements_.size(), Mat3::Zero());
  set_elements(std::move(vertices), mesh.vertex_count());
  set_rigidity(rigidity_Nm);
}

void PlateBendingTerm::set_rigidity(const Mat3& rigidity_Nm) {
  require_rigidity(rigidity_Nm);
  const Mat3 compliance = rigidity_Nm.inverse();
  const Eigen::DiagonalMatrix<double, 3> frobenius(1.0, 1.0, 0.5);
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    PlateElement& e = elements_[i];
    const int m = e.hinge_count;
    const Eigen::MatrixXd a = angle_per_curvature_[i].topRows(m);
    const Eigen::MatrixXd s = a * compliance * a.transpose();  // m x m, symmetric positive semi-definite
    // The pseudo-inverse, not the inverse: on some refined meshes two hinges of a triangle
    // respond to curvature in proportion (their rows of A are parallel), and s is singular
    // to rounding. An inverse then either fails or, where the rounding lets it pass, makes
    // the combination of angles no curvature explains enormously stiff. With the
    // pseudo-inverse that combination carries no energy here (each hinge also belongs to its
    // neighbour's element, which does see it).
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(s);
    const Eigen::VectorXd& lambda = eigen.eigenvalues();
    const double cutoff = 1e-10 * lambda.cwiseAbs().maxCoeff();
    Eigen::VectorXd inverse_lambda = Eigen::VectorXd::Zero(m);
    for (int k = 0; k < m; ++k) {
      if (lambda(k) > cutoff) inverse_lambda(k) = 1.0 / lambda(k);
    }
    const Eigen::MatrixXd s_inv =
        eigen.eigenvectors() * inverse_lambda.asDiagonal() * eigen.eigenvectors().transpose();
    const Eigen::MatrixXd curvature = compliance * a.transpose() * s_inv;  // 3 x m
    e.q.setZero();
    e.q.topLeftCorner(m, m) = area_m2_[i] * s_inv;
    e.r.setZero();
    e.r.topLeftCorner(m, m) = curvature.transpose() * frobenius * curvature;
    curvature_per_angle_[i].setZero();
    curvature_per_angle_[i].leftCols(m) = curvature;
  }
  rigidity_ = rigidity_Nm;  // the rest angles depend on the geometry alone and stay
}

void PlateBendingTerm::set_rest_curvature(const CurvatureTensor& k) {
  if (k == rest_curvature_) return;
  const Vec3 kappa(k.uu_1_m, k.vv_1_m, 2.0 * k.uv_1_m);
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    elements_[i].rest_angle_rad = angle_per_curvature_[i] * kappa;
  }
  rest_curvature_ = k;
}

void PlateBendingTerm::set_stiffening(double beta_m2) {
  if (!(std::isfinite(beta_m2) && beta_m2 >= 0.0)) {
    throw std::invalid_argument("plate bending: stiffening beta must be a finite number >= 0 (m^2), "
                                "got " + std::to_string(beta_m2));
  }
  for (PlateElement& e : elements_) e.stiffening_m2 = beta_m2;
}

Vec3 PlateBendingTerm::curvature(const VecX& x, int element) const {
  const PlateElement& e = elements_[element];
  Vec3 d = Vec3::Zero();
  for (int j = 0; j < e.hinge_count; ++j) {
    const auto local = plate_hinge_local_vertices(e.edge[j]);
    Vec12 xh;
    for (int k = 0; k < 4; ++k) xh.segment<3>(3 * k) = x.segment<3>(3 * e.v[local[k]]);
    d(j) = dihedral_angle(xh, nullptr, nullptr) - e.rest_angle_rad(j);
  }
  const Vec3 kappa = curvature_per_angle_[element] * d;
  return {kappa(0), kappa(1), 0.5 * kappa(2)};
}

}  // namespace twin
