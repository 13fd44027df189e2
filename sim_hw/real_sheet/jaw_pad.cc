#include "sim_hw/real_sheet/jaw_pad.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "sim_hw/real_sheet/cross_matrix.h"

namespace sim_hw::real_sheet {
namespace {

using Mat3 = Eigen::Matrix3d;

// Rings of sample points covering the annulus [r0, r1], each ring `width` wide, points about
// `spacing` apart along the ring; area weights sum to the annulus's area.
void add_rings(double r0, double r1, double spacing, const std::function<double(double)>& hold,
               std::vector<std::array<double, 4>>& points) {
  if (r1 <= r0) return;
  const int rings = std::max(1, static_cast<int>(std::ceil((r1 - r0) / spacing)));
  const double width = (r1 - r0) / rings;
  for (int k = 0; k < rings; ++k) {
    const double rho = r0 + (k + 0.5) * width;
    const int n = std::max(6, static_cast<int>(std::ceil(2 * std::numbers::pi * rho / spacing)));
    const double area = 2 * std::numbers::pi * rho * width / n;
    for (int a = 0; a < n; ++a) {
      const double phi = 2 * std::numbers::pi * (a + 0.5 * (k % 2)) / n;
      points.push_back({rho * std::cos(phi), rho * std::sin(phi), area, hold(rho)});
    }
  }
}

}  // namespace

Mat3 rotation_exp(const Vec3& w) {
  const double angle = w.norm();
  if (angle < 1e-300) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

JawPad make_jaw_pad(const Grid& grid, const std::string& id, const Vec2& point, JawKind kind,
                    const JawPadOptions& o) {
  if (!(o.grip_radius_m >= 0) || !(o.extension_m >= 0) || !(o.pad_stiffness_N_m3 > 0)) {
    throw std::invalid_argument(fmt::format("real sheet: jaw '{}': radius {} m, extension {} m, stiffness {} N/m^3 "
                                            "(expected radius and extension >= 0, stiffness > 0)",
                                            id, o.grip_radius_m, o.extension_m, o.pad_stiffness_N_m3));
  }
  if (point.x() < -1e-9 || point.y() < -1e-9 || point.x() > grid.width_m() + 1e-9 ||
      point.y() > grid.height_m() + 1e-9) {
    throw std::invalid_argument(fmt::format("real sheet: jaw '{}' at ({}, {}) m is off the {} x {} m sheet", id,
                                            point.x(), point.y(), grid.width_m(), grid.height_m()));
  }
  JawPad pad;
  pad.id = id;
  pad.kind = kind;
  pad.material_point_m = point;
  pad.grip_radius_m = o.grip_radius_m;
  const Vec2 cell = grid.cell_size_at(point);
  const double spacing = std::min({o.sample_spacing_m, cell.x() / 3, cell.y() / 3});
  std::vector<std::array<double, 4>> points;  // du, dv (m), area (m^2), hold
  // A pin (radius 0) still holds a small pad, a third of a millimetre, so that it has a centre.
  const double r = std::max(o.grip_radius_m, 3e-4);
  add_rings(0.0, r, std::min(spacing, r / 3), [](double) { return 1.0; }, points);
  if (o.extension_strength > 0 && o.extension_m > 0) {
    const double w = o.extension_m, s = o.extension_strength;
    add_rings(r, r + w, spacing, [&](double rho) { return s * std::sqrt(std::max(0.0, 1.0 - std::pow((rho - r) / w, 2))); },
              points);
  }
  double total_N_m = 0;
  for (const auto& [du, dv, area, hold] : points) {
    if (hold <= 0) continue;
    const Vec2 uv = point + Vec2(du, dv);
    // Only the sheet is held: a pad hanging over the edge holds nothing there.
    if (uv.x() < 0 || uv.y() < 0 || uv.x() > grid.width_m() || uv.y() > grid.height_m()) continue;
    JawSample sample;
    sample.at = grid.locate(uv);
    sample.offset_m = Vec3(du, dv, 0.0);
    sample.area_m2 = area;
    sample.stiffness_N_m = o.pad_stiffness_N_m3 * area * hold;
    total_N_m += sample.stiffness_N_m;
    pad.samples.push_back(sample);
  }
  if (o.slip_compliance_m_N > 0) pad.tangential_share = std::min(1.0, 1.0 / (o.slip_compliance_m_N * total_N_m));
  return pad;
}

std::vector<int> pad_nodes(const JawPad& pad) {
  std::vector<int> nodes;
  for (const JawSample& s : pad.samples) {
    for (int k = 0; k < 4; ++k) {
      if (s.at.weights[k] != 0.0) nodes.push_back(s.at.nodes[k]);
    }
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

double jaw_pad_energy(const JawPad& pad, const VecX& x, const Vec3& c, const Mat3& R, const std::vector<int>& nodes,
                      Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  const bool pivot = pad.kind == JawKind::kPivot;
  const int rot = 3 * static_cast<int>(nodes.size());  // first rotation row (pivot only)
  const Vec3 Kl(pad.tangential_share, pad.tangential_share, 1.0);
  double energy = 0;
  for (const JawSample& s : pad.samples) {
    Vec3 X = Vec3::Zero();
    int local[4];
    for (int k = 0; k < 4; ++k) {
      X += s.at.weights[k] * x.segment<3>(3 * s.at.nodes[k]);
      local[k] = s.at.weights[k] != 0.0
                     ? 3 * static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), s.at.nodes[k]) - nodes.begin())
                     : -1;
    }
    const Vec3 z = X - c;
    const Vec3 rho = R.transpose() * z - s.offset_m;
    const Vec3 grho = s.stiffness_N_m * Kl.cwiseProduct(rho);  // dE/drho
    energy += 0.5 * rho.dot(grho);
    if (!g && !H) continue;
    // dE/dX = R grho; the world-frame stiffness K = R diag(k Kl) R^T.
    const Vec3 h = R * grho;
    const Mat3 K = R * (s.stiffness_N_m * Kl).asDiagonal() * R.transpose();
    if (g) {
      for (int k = 0; k < 4; ++k) {
        if (local[k] >= 0) g->segment<3>(local[k]) += s.at.weights[k] * h;
      }
      // rho(omega) = R^T exp(-[omega]x) z - d: d rho/d omega = R^T [z]x, so dE/domega = [z]x^T h = h x z... as
      // [z]x^T h = -z x h = h x z.
      if (pivot) g->segment<3>(rot) += h.cross(z);
    }
    if (!H) continue;
    for (int a = 0; a < 4; ++a) {
      if (local[a] < 0) continue;
      for (int b = 0; b < 4; ++b) {
        if (local[b] >= 0) H->block<3, 3>(local[a], local[b]) += s.at.weights[a] * s.at.weights[b] * K;
      }
    }
    if (!pivot) continue;
    // Rotation blocks: Gauss-Newton part through d rho/d omega = R^T [z]x, plus the second-order
    // terms of exp(-[omega]x) z = z - omega x z + 1/2 omega x (omega x z) contracted with h.
    const Mat3 Z = cross_matrix(z);
    H->block<3, 3>(rot, rot) += Z.transpose() * K * Z + 0.5 * (z * h.transpose() + h * z.transpose()) -
                                z.dot(h) * Mat3::Identity();
    // d2E/domega dX: (R^T [z]x)^T diag R^T + d/dX of (h x z) at fixed grho = [h]x.
    const Mat3 cross = Z.transpose() * K + cross_matrix(h);
    for (int a = 0; a < 4; ++a) {
      if (local[a] < 0) continue;
      H->block<3, 3>(rot, local[a]) += s.at.weights[a] * cross;
      H->block<3, 3>(local[a], rot) += s.at.weights[a] * cross.transpose();
    }
  }
  return energy;
}

}  // namespace sim_hw::real_sheet
