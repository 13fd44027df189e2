#include "sim_hw/spline_shell/jaw_grip.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::spline_shell {
namespace {

// The elements (first, last) along one axis whose span meets the grip's reach [lo, hi].
std::pair<int, int> elements_meeting(const KnotVector& k, double lo, double hi) {
  const std::vector<double>& b = k.breaks();
  int first = k.element_count(), last = -1;
  for (int e = 0; e < k.element_count(); ++e) {
    if (b[e + 1] > lo && b[e] < hi) first = std::min(first, e), last = std::max(last, e);
  }
  return {first, last};
}

// Calls visit(element, point, hold) for every quadrature point of the grip with a positive
// hold (the pad's own points only when `with_pad`).
template <typename Visit>
void for_grip_points(const SplinePatch& patch, const JawGrip& grip, const SquareJaw& jaw, bool with_pad, Visit visit) {
  const double reach = jaw.half_side_m + grip.knot_extension_m();
  const Vec2& m = jaw.material_point_m;
  const auto [u0, u1] = elements_meeting(patch.u(), m.x() - reach, m.x() + reach);
  const auto [v0, v1] = elements_meeting(patch.v(), m.y() - reach, m.y() + reach);
  for (int ev = v0; ev <= v1; ++ev) {
    for (int eu = u0; eu <= u1; ++eu) {
      const int e = ev * patch.u().element_count() + eu;
      for (const QuadraturePoint& q : patch.element_points(e)) {
        if (!with_pad && distance_to_pad_m(jaw, q.uv_m) == 0.0) continue;
        const double hold = grip_hold(grip, jaw, q.uv_m);
        if (hold > 0) visit(e, q, hold);
      }
    }
  }
}

}  // namespace

JawGrip jaw_grip(const real_sheet::SheetMaterial& material) {
  if (!(material.pad_extension_m >= 0) || !(material.pad_strength >= 0) || !(material.slip_compliance_m_N >= 0)) {
    throw std::invalid_argument(fmt::format(
        "spline shell: jaws with extension {} m, strength {}, slip compliance {} m/N (expected each >= 0)",
        material.pad_extension_m, material.pad_strength, material.slip_compliance_m_N));
  }
  JawGrip grip;
  grip.extension_m = material.pad_extension_m;
  grip.extension_strength = material.pad_strength;
  grip.slip_compliance_m_N = material.slip_compliance_m_N;
  return grip;
}

double grip_hold(const JawGrip& grip, const SquareJaw& jaw, const Vec2& uv_m) {
  const Vec2 beyond = ((uv_m - jaw.material_point_m).cwiseAbs().array() - jaw.half_side_m).cwiseMax(0.0);
  if (beyond.isZero()) return 1.0;
  if (!grip.widens()) return 0.0;
  const double w = grip.extension_m;
  if (beyond.x() >= w || beyond.y() >= w) return 0.0;
  return grip.extension_strength * std::sqrt((1.0 - std::pow(beyond.x() / w, 2)) * (1.0 - std::pow(beyond.y() / w, 2)));
}

double grip_tangential_share(const SplinePatch& patch, const JawGrip& grip, const SquareJaw& jaw) {
  if (!grip.slips()) return 1.0;
  double total_N_m = 0;
  for_grip_points(patch, grip, jaw, true,
                  [&](int, const QuadraturePoint& q, double hold) { total_N_m += grip.pad_stiffness_N_m3 * q.area_m2 * hold; });
  return total_N_m > 0 ? std::min(1.0, 1.0 / (grip.slip_compliance_m_N * total_N_m)) : 1.0;
}

double grip_energy(const SplinePatch& patch, const JawGrip& grip, const SquareJaw& jaw, const Vec3& centre_m,
                   const Eigen::Matrix3d& rotation, const VecX& x, VecX* gradient,
                   real_sheet::BlockSparseMatrix* hessian) {
  if (!grip.widens() && !grip.slips()) return 0.0;
  const double tau = grip_tangential_share(patch, grip, jaw);
  const Eigen::Vector3d share(tau, tau, 1.0);
  // The springs' stiffness in the world frame per unit k A hold: R diag(tau, tau, 1) R^T.
  const Eigen::Matrix3d K = rotation * share.asDiagonal() * rotation.transpose();
  const Vec2& m = jaw.material_point_m;
  double energy = 0;
  int element = -1;
  Eigen::MatrixXd H;
  const auto flush = [&] {
    if (hessian && element >= 0) hessian->add(patch.element_controls(element), H);
  };
  for_grip_points(patch, grip, jaw, grip.slips(), [&](int e, const QuadraturePoint& q, double hold) {
    const std::vector<int>& controls = patch.element_controls(e);
    const int n = static_cast<int>(controls.size());
    if (e != element) {
      flush();
      element = e;
      if (hessian) H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    }
    Vec3 X = Vec3::Zero();
    for (int k = 0; k < n; ++k) X += q.w(kValue, k) * x.segment<3>(3 * controls[k]);
    const Vec3 rho = rotation.transpose() * (X - centre_m) - Vec3(q.uv_m.x() - m.x(), q.uv_m.y() - m.y(), 0.0);
    const double stiffness_N_m = grip.pad_stiffness_N_m3 * q.area_m2 * hold;
    energy += 0.5 * stiffness_N_m * rho.dot(share.cwiseProduct(rho));
    if (gradient) {
      const Vec3 f = stiffness_N_m * (rotation * share.cwiseProduct(rho));
      for (int k = 0; k < n; ++k) gradient->segment<3>(3 * controls[k]) += q.w(kValue, k) * f;
    }
    if (hessian) {
      for (int k = 0; k < n; ++k) {
        for (int l = 0; l < n; ++l) H.block<3, 3>(3 * k, 3 * l) += stiffness_N_m * q.w(kValue, k) * q.w(kValue, l) * K;
      }
    }
  });
  flush();
  return energy;
}

}  // namespace sim_hw::spline_shell
