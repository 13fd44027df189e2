#include "twin/model/clamp_slip_term.h"

#include <stdexcept>
#include <string>

#include "twin/model/shell_model.h"

namespace twin {

ClampSlipTerm::ClampSlipTerm(int vertex_count) : vertex_count_(vertex_count), coupling_(*this) {}

void ClampSlipTerm::set_clamps(const SheetMesh& mesh, const ClampSet& clamps) {
  if (mesh.vertex_count() != vertex_count_) {
    throw std::invalid_argument("ClampSlipTerm::set_clamps: the mesh has " + std::to_string(mesh.vertex_count()) +
                                " vertices, expected " + std::to_string(vertex_count_));
  }
  const std::vector<double> areas_m2 = lumped_vertex_masses(mesh, 1.0);
  clamps_ = clamps;
  springs_.clear();
  vertices_.clear();
  coupling_.vertices_.clear();
  coupling_.springs_.clear();
  for (int c = 0; c < clamps.size(); ++c) {
    const std::vector<int>& patch = clamps[c].vertices();
    double patch_area_m2 = 0.0;
    for (int v : patch) patch_area_m2 += areas_m2[v];
    const int first = spring_count();
    for (std::size_t k = 0; k < patch.size(); ++k) {
      springs_.push_back({c, static_cast<int>(k), areas_m2[patch[k]] / patch_area_m2});
      vertices_.push_back(patch[k]);
    }
    for (int i = first; i < spring_count(); ++i) {
      for (int j = i + 1; j < spring_count(); ++j) {
        coupling_.vertices_.insert(coupling_.vertices_.end(), {vertices_[i], vertices_[j]});
        coupling_.springs_.push_back({i, j});
      }
    }
  }
  set_poses(std::vector<ClampPose>(clamps.size()));
}

void ClampSlipTerm::set_poses(const std::vector<ClampPose>& poses) const {
  if (!has_clamps()) return;
  if (static_cast<int>(poses.size()) != clamp_count()) {
    throw std::invalid_argument("ClampSlipTerm::set_poses: " + std::to_string(poses.size()) + " clamp poses for " +
                                std::to_string(clamp_count()) + " clamps");
  }
  held_m_.resize(springs_.size());
  for (std::size_t e = 0; e < springs_.size(); ++e) {
    held_m_[e] = clamps_[springs_[e].clamp].held_position(springs_[e].index, poses[springs_[e].clamp]);
  }
  normal_.resize(poses.size());
  engaged_.resize(poses.size());
  for (std::size_t c = 0; c < poses.size(); ++c) {
    normal_[c] = poses[c].rotation.col(2).normalized();
    engaged_[c] = poses[c].engaged ? 1 : 0;
  }
}

Mat3 ClampSlipTerm::softening(int clamp) const {
  if (!engaged_[clamp]) return Mat3::Zero();
  const Vec3& n = normal_[clamp];
  return (Mat3::Identity() - n * n.transpose()) *
         (1.0 / (compliance_m_N_ + kRigidJawCompliance_m_N) - 1.0 / kRigidJawCompliance_m_N);
}

// Both parts sum their few blocks serially: an OpenMP region would cost more.

double ClampSlipTerm::evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                               HessianMode /*mode: the energy is convex*/) const {
  double energy = 0.0;
  for (int e = 0; e < spring_count(); ++e) {
    const Spring& s = springs_[e];
    if (!engaged_[s.clamp]) continue;
    const Mat3 a = (s.area_share / kRigidJawCompliance_m_N) * Mat3::Identity() +
                   s.area_share * s.area_share * softening(s.clamp);
    const Vec3 d = offset(x, e);
    const Vec3 force = a * d;
    energy += 0.5 * d.dot(force);
    if (grad) grad->segment<3>(3 * vertices_[e]) += force;
    if (hess) hess->pattern->add<1>(hess->term, e, a);
  }
  return energy;
}

double ClampSlipTerm::Coupling::evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                                         HessianMode /*mode*/) const {
  double energy = 0.0;
  for (std::size_t p = 0; p < springs_.size(); ++p) {
    const auto [i, j] = springs_[p];
    const Spring& si = slip_.springs_[i];
    if (!slip_.engaged_[si.clamp]) continue;
    const Mat3 a = si.area_share * slip_.springs_[j].area_share * slip_.softening(si.clamp);  // symmetric
    const Vec3 di = slip_.offset(x, i), dj = slip_.offset(x, j);
    energy += di.dot(a * dj);
    if (grad) {
      grad->segment<3>(3 * slip_.vertices_[i]) += a * dj;
      grad->segment<3>(3 * slip_.vertices_[j]) += a * di;
    }
    if (hess) {
      Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
      h.block<3, 3>(0, 3) = a;
      h.block<3, 3>(3, 0) = a;
      hess->pattern->add<2>(hess->term, static_cast<int>(p), h);
    }
  }
  return energy;
}

}  // namespace twin
