#include "twin/model/clamp.h"

#include "twin/mesh/material_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

namespace twin {
namespace {

std::string describe(const Vec2& p) { return fmt::format("({:.4g}, {:.4g}) m", p.x(), p.y()); }

}  // namespace

ClampPose interpolate(const ClampPose& a, const ClampPose& b, double t) {
  ClampPose p;
  p.engaged = b.engaged;
  p.position_m = (1.0 - t) * a.position_m + t * b.position_m;
  p.rotation = Eigen::Quaterniond(a.rotation).slerp(t, Eigen::Quaterniond(b.rotation)).toRotationMatrix();
  return p;
}

Clamp::Clamp(const SheetMesh& mesh, const ClampSpec& spec) : spec_(spec) {
  const std::string who = "clamp '" + spec.id + "'";
  const auto host = locate_material_point(mesh, spec.material_point_m);
  if (!host) {
    throw std::invalid_argument(who + ": material point " + describe(spec.material_point_m) +
                                " is not on the sheet");
  }
  if (!(std::isfinite(spec.grip_radius_m) && spec.grip_radius_m >= 0.0)) {
    throw std::invalid_argument(who + ": grip_radius_m must be >= 0 (m)");
  }
  int nearest = -1;
  double nearest_distance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const double d = (mesh.rest_uv[i] - spec.material_point_m).norm();
    if (d <= spec.grip_radius_m) vertices_.push_back(i);
    if (d < nearest_distance) {
      nearest_distance = d;
      nearest = i;
    }
  }
  if (spec.grip_radius_m == 0.0) {
    vertices_ = {nearest};  // a pin: holds one vertex and lets the sheet turn about it
  } else if (vertices_.size() < 3) {
    // Jaws resist turning. On a mesh coarser than the jaws, fewer than three vertices fall
    // inside the grip and the clamp would act as a pin; the host triangle keeps it a grip,
    // so the same clamp behaves alike on coarse and fine meshes.
    for (int v : host->vertices) {
      if (std::find(vertices_.begin(), vertices_.end(), v) == vertices_.end()) vertices_.push_back(v);
    }
  }
  host_triangle_ = host->vertices;
  host_weights_ = host->weights;
  Mat2 edges;
  edges.col(0) = mesh.rest_uv[host_triangle_[1]] - mesh.rest_uv[host_triangle_[0]];
  edges.col(1) = mesh.rest_uv[host_triangle_[2]] - mesh.rest_uv[host_triangle_[0]];
  const Mat2 inv = edges.inverse();
  host_gradients_.row(1) = inv.row(0);
  host_gradients_.row(2) = inv.row(1);
  host_gradients_.row(0) = -inv.row(0) - inv.row(1);
  for (int v : vertices_) offsets_m_.push_back(mesh.rest_uv[v] - spec.material_point_m);
}

void Clamp::hold(const ClampPose& pose, VecX& x) const {
  for (std::size_t k = 0; k < vertices_.size(); ++k) x.segment<3>(3 * vertices_[k]) = held_position(static_cast<int>(k), pose);
}

Vec3 Clamp::material_point_position(const VecX& x) const {
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 3; ++k) p += host_weights_(k) * x.segment<3>(3 * host_triangle_[k]);
  return p;
}

Mat3 Clamp::material_frame(const VecX& x) const {
  Eigen::Matrix<double, 3, 2> f = Eigen::Matrix<double, 3, 2>::Zero();  // (U V), paper Eq. 1
  for (int k = 0; k < 3; ++k) f += x.segment<3>(3 * host_triangle_[k]) * host_gradients_.row(k);
  // Polar decomposition F = R S: R = F (F^T F)^(-1/2), the rotation without the stretch.
  Eigen::SelfAdjointEigenSolver<Mat2> eig(f.transpose() * f);
  const Mat2 inverse_root = eig.eigenvectors() *
                            eig.eigenvalues().cwiseMax(1e-30).cwiseSqrt().cwiseInverse().asDiagonal() *
                            eig.eigenvectors().transpose();
  const Eigen::Matrix<double, 3, 2> r = f * inverse_root;
  Mat3 frame;
  frame.col(0) = r.col(0);
  frame.col(1) = r.col(1);
  frame.col(2) = r.col(0).cross(r.col(1)).normalized();
  return frame;
}

ClampSet::ClampSet(const SheetMesh& mesh, const std::vector<ClampSpec>& specs) {
  std::set<std::string> ids;
  std::vector<int> owner(mesh.vertex_count(), -1);
  for (const ClampSpec& spec : specs) {
    if (!ids.insert(spec.id).second) {
      throw std::invalid_argument("clamp id '" + spec.id + "' is used twice");
    }
    clamps_.emplace_back(mesh, spec);
    const int index = static_cast<int>(clamps_.size()) - 1;
    for (int v : clamps_.back().vertices()) {
      if (owner[v] >= 0) {
        throw std::invalid_argument("clamps '" + clamps_[owner[v]].spec().id + "' and '" +
                                    spec.id + "' grip the same part of the sheet");
      }
      owner[v] = index;
    }
  }
}

int ClampSet::index_of(const std::string& id) const {
  for (int i = 0; i < size(); ++i) {
    if (clamps_[i].spec().id == id) return i;
  }
  throw std::invalid_argument("no clamp with id '" + id + "'");
}

std::vector<char> ClampSet::fixed_vertices(int vertex_count,
                                           const std::vector<ClampPose>& poses) const {
  std::vector<char> fixed(vertex_count, 0);
  for (int i = 0; i < size(); ++i) {
    if (!poses[i].engaged) continue;
    for (int v : clamps_[i].vertices()) fixed[v] = 1;
  }
  return fixed;
}

void ClampSet::hold(const std::vector<ClampPose>& poses, VecX& x) const {
  for (int i = 0; i < size(); ++i) {
    if (poses[i].engaged) clamps_[i].hold(poses[i], x);
  }
}

VecX place_flat(const SheetMesh& mesh, const SheetPlacement& placement) {
  VecX x(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) x.segment<3>(3 * i) = placement.to_world(mesh.rest_uv[i]);
  return x;
}

}  // namespace twin
