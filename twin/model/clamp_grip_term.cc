#include "twin/model/clamp_grip_term.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "twin/model/shell_model.h"

namespace twin {

ClampGripTerm::ClampGripTerm(int vertex_count) : vertex_count_(vertex_count) {}

void ClampGripTerm::set_clamps(const SheetMesh& mesh, const ClampSet& clamps) {
  if (mesh.vertex_count() != vertex_count_) {
    throw std::invalid_argument("ClampGripTerm::set_clamps: the mesh has " + std::to_string(mesh.vertex_count()) +
                                " vertices, expected " + std::to_string(vertex_count_));
  }
  std::vector<char> held(mesh.vertex_count(), 0);
  for (int c = 0; c < clamps.size(); ++c) {
    for (int v : clamps[c].vertices()) held[v] = 1;
  }
  const std::vector<double> areas_m2 = lumped_vertex_masses(mesh, 1.0);
  std::vector<int> vertices;
  springs_.clear();
  for (int c = 0; c < clamps.size(); ++c) {
    const ClampSpec& spec = clamps[c].spec();
    const std::array<int, 3>& host = clamps[c].host_triangle();
    // Affine coordinates in the host triangle's rest shape: u = u0 + E (l1, l2), l0 = 1 - l1 - l2.
    Eigen::Matrix2d edges;
    edges.col(0) = mesh.rest_uv[host[1]] - mesh.rest_uv[host[0]];
    edges.col(1) = mesh.rest_uv[host[2]] - mesh.rest_uv[host[0]];
    const Eigen::Matrix2d inverse = edges.inverse();
    for (int i = 0; i < mesh.vertex_count(); ++i) {
      if (held[i]) continue;
      const double excess_m = (mesh.rest_uv[i] - spec.material_point_m).norm() - spec.grip_radius_m;
      if (excess_m > kMaxClampGripWidth_m + std::sqrt(areas_m2[i])) continue;
      const Vec2 l = inverse * (mesh.rest_uv[i] - mesh.rest_uv[host[0]]);
      Spring s;
      s.clamp = c;
      s.affine = Vec3(1.0 - l.x() - l.y(), l.x(), l.y());
      s.excess_m = excess_m;
      s.area_m2 = areas_m2[i];
      s.size_m = std::sqrt(areas_m2[i]);
      springs_.push_back(s);
      vertices.insert(vertices.end(), {i, host[0], host[1], host[2]});
    }
  }
  clamp_count_ = clamps.size();
  engaged_.assign(clamp_count_, 1);
  vertices_ = std::move(vertices);
}

void ClampGripTerm::set_engaged(const std::vector<ClampPose>& poses) const {
  if (clamp_count_ == 0) return;
  if (static_cast<int>(poses.size()) != clamp_count_) {
    throw std::invalid_argument("ClampGripTerm::set_engaged: " + std::to_string(poses.size()) +
                                " clamp poses for " + std::to_string(clamp_count_) + " clamps");
  }
  for (int c = 0; c < clamp_count_; ++c) engaged_[c] = poses[c].engaged ? 1 : 0;
}

double ClampGripTerm::spring_stiffness_N_m(int spring) const {
  const Spring& s = springs_[spring];
  if (!engaged_[s.clamp] || strength_ == 0.0) return 0.0;
  const double covered = std::clamp(1.0 + (width_m_ - s.excess_m) / s.size_m, 0.0, 1.0);
  return strength_ * kGripStiffness_N_m3 * s.area_m2 * covered;
}

double ClampGripTerm::evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                               HessianMode /*mode: the energy is convex*/) const {
  if (strength_ == 0.0) return 0.0;
  double energy = 0.0;
  for (int e = 0; e < spring_count(); ++e) {
    const double k_N_m = spring_stiffness_N_m(e);
    if (k_N_m == 0.0) continue;  // a released clamp, or beyond the jaws
    const int* v = &vertices_[4 * e];
    const Vec3& l = springs_[e].affine;
    // r = A xe with A = [I, -l0 I, -l1 I, -l2 I].
    const Eigen::Vector4d a(1.0, -l(0), -l(1), -l(2));
    Vec3 r = Vec3::Zero();
    for (int k = 0; k < 4; ++k) r += a(k) * x.segment<3>(3 * v[k]);
    energy += 0.5 * k_N_m * r.squaredNorm();
    if (grad) {
      for (int k = 0; k < 4; ++k) grad->segment<3>(3 * v[k]) += k_N_m * a(k) * r;
    }
    if (hess) {
      Eigen::Matrix<double, 12, 12> h;
      for (int p = 0; p < 4; ++p) {
        for (int q = 0; q < 4; ++q) h.block<3, 3>(3 * p, 3 * q) = k_N_m * a(p) * a(q) * Mat3::Identity();
      }
      hess->pattern->add<4>(hess->term, e, h);
    }
  }
  return energy;
}

}  // namespace twin
