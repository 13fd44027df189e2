#include "sim_hw/spline_shell/spline_patch.h"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <fmt/format.h>

namespace sim_hw::spline_shell {
namespace {

// Tensor-product weights from the two directions' values (each: rows = derivative order 0..2).
Eigen::Matrix<double, 6, Eigen::Dynamic> tensor_weights(const KnotVector::Values& a, const KnotVector::Values& b) {
  const int p = static_cast<int>(a.values.cols()) - 1;
  Eigen::Matrix<double, 6, Eigen::Dynamic> w(6, (p + 1) * (p + 1));
  for (int kv = 0; kv <= p; ++kv) {
    for (int ku = 0; ku <= p; ++ku) {
      const int k = kv * (p + 1) + ku;
      w(kValue, k) = a.values(0, ku) * b.values(0, kv);
      w(kU, k) = a.values(1, ku) * b.values(0, kv);
      w(kV, k) = a.values(0, ku) * b.values(1, kv);
      w(kUU, k) = a.values(2, ku) * b.values(0, kv);
      w(kVV, k) = a.values(0, ku) * b.values(2, kv);
      w(kUV, k) = a.values(1, ku) * b.values(1, kv);
    }
  }
  return w;
}

// The collocation matrix A(i, j) = N_j(g_i) at the Greville abscissae.
Eigen::MatrixXd collocation(const KnotVector& k) {
  const std::vector<double> g = k.greville();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(k.basis_count(), k.basis_count());
  for (int i = 0; i < k.basis_count(); ++i) {
    const KnotVector::Values a = k.evaluate(g[i], 0);
    for (int m = 0; m <= k.degree(); ++m) A(i, a.first + m) = a.values(0, m);
  }
  return A;
}

}  // namespace

SplinePatch::SplinePatch(KnotVector u, KnotVector v, int gauss_points) : u_(std::move(u)), v_(std::move(v)) {
  const int p = u_.degree();
  if (v_.degree() != p) {
    throw std::invalid_argument(fmt::format("spline shell: degrees {} in u and {} in v (expected equal)", p, v_.degree()));
  }
  const int q = gauss_points == 0 ? p + 1 : gauss_points;
  if (q < p + 1) {
    throw std::invalid_argument(fmt::format("spline shell: {} Gauss points per direction (expected at least p + 1 = {})", q, p + 1));
  }
  const int eu_count = u_.element_count(), ev_count = v_.element_count();
  controls_.resize(element_count());
  points_.resize(element_count());
  for (int ev = 0; ev < ev_count; ++ev) {
    const GaussRule rv = gauss_legendre(q, v_.breaks()[ev], v_.breaks()[ev + 1]);
    for (int eu = 0; eu < eu_count; ++eu) {
      const int e = ev * eu_count + eu;
      for (int kv = 0; kv <= p; ++kv) {
        for (int ku = 0; ku <= p; ++ku) controls_[e].push_back(control(u_.first_basis(eu) + ku, v_.first_basis(ev) + kv));
      }
      const GaussRule ru = gauss_legendre(q, u_.breaks()[eu], u_.breaks()[eu + 1]);
      for (int a = 0; a < q; ++a) {
        for (int b = 0; b < q; ++b) {
          points_[e].push_back(point_in(e, Vec2(ru.points[b], rv.points[a]), ru.weights[b] * rv.weights[a]));
        }
      }
    }
  }
}

int SplinePatch::element_at(const Vec2& uv_m) const {
  return v_.element_at(uv_m.y()) * u_.element_count() + u_.element_at(uv_m.x());
}

PointWeights SplinePatch::weights_at(const Vec2& uv_m) const {
  const int e = element_at(uv_m);
  const int eu = e % u_.element_count(), ev = e / u_.element_count();
  const Vec2 uv(std::clamp(uv_m.x(), 0.0, width_m()), std::clamp(uv_m.y(), 0.0, height_m()));
  return PointWeights{controls_[e], tensor_weights(u_.evaluate_in(eu, uv.x(), 2), v_.evaluate_in(ev, uv.y(), 2))};
}

QuadraturePoint SplinePatch::point_in(int element, const Vec2& uv_m, double area_m2) const {
  const int eu = element % u_.element_count(), ev = element / u_.element_count();
  QuadraturePoint point;
  point.uv_m = uv_m;
  point.area_m2 = area_m2;
  point.w = tensor_weights(u_.evaluate_in(eu, uv_m.x(), 2), v_.evaluate_in(ev, uv_m.y(), 2));
  return point;
}

namespace {
Vec3 combine(const VecX& x, const PointWeights& pw, int row) {
  Vec3 r = Vec3::Zero();
  for (std::size_t k = 0; k < pw.controls.size(); ++k) r += pw.w(row, k) * x.segment<3>(3 * pw.controls[k]);
  return r;
}
}  // namespace

Vec3 SplinePatch::position(const VecX& x, const Vec2& uv_m) const { return combine(x, weights_at(uv_m), kValue); }

Vec3 SplinePatch::normal(const VecX& x, const Vec2& uv_m) const {
  const PointWeights pw = weights_at(uv_m);
  return combine(x, pw, kU).cross(combine(x, pw, kV)).normalized();
}

Vec3 SplinePatch::second_form(const VecX& x, const Vec2& uv_m) const {
  const PointWeights pw = weights_at(uv_m);
  const Vec3 n = combine(x, pw, kU).cross(combine(x, pw, kV)).normalized();
  return Vec3(combine(x, pw, kUU).dot(n), combine(x, pw, kVV).dot(n), combine(x, pw, kUV).dot(n));
}

VecX SplinePatch::flat_positions() const {
  return interpolate([](const Vec2& uv) { return Vec3(uv.x(), uv.y(), 0.0); });
}

VecX SplinePatch::interpolate(const std::function<Vec3(const Vec2&)>& shape) const {
  // Tensor collocation: F = A_u P A_v^T per coordinate, F(i, j) the shape at (g_i, g_j).
  const std::vector<double> gu = u_.greville(), gv = v_.greville();
  const Eigen::PartialPivLU<Eigen::MatrixXd> Au(collocation(u_)), Av(collocation(v_));
  VecX x(3 * control_count());
  Eigen::MatrixXd F[3];
  for (auto& f : F) f.resize(nu(), nv());
  for (int j = 0; j < nv(); ++j) {
    for (int i = 0; i < nu(); ++i) {
      const Vec3 s = shape(Vec2(gu[i], gv[j]));
      for (int c = 0; c < 3; ++c) F[c](i, j) = s[c];
    }
  }
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd Pu = Au.solve(F[c]);                          // A_u^-1 F
    const Eigen::MatrixXd P = Av.solve(Pu.transpose()).transpose();     // (A_v^-1 (A_u^-1 F)^T)^T
    for (int j = 0; j < nv(); ++j) {
      for (int i = 0; i < nu(); ++i) x[3 * control(i, j) + c] = P(i, j);
    }
  }
  return x;
}

VecX refine_controls(const SplinePatch& coarse, const VecX& x, const SplinePatch& fine) {
  const Eigen::MatrixXd Tu = prolongation(coarse.u(), fine.u()), Tv = prolongation(coarse.v(), fine.v());
  VecX out(3 * fine.control_count());
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd P(coarse.nu(), coarse.nv());
    for (int j = 0; j < coarse.nv(); ++j) {
      for (int i = 0; i < coarse.nu(); ++i) P(i, j) = x[3 * coarse.control(i, j) + c];
    }
    const Eigen::MatrixXd Q = Tu * P * Tv.transpose();
    for (int j = 0; j < fine.nv(); ++j) {
      for (int i = 0; i < fine.nu(); ++i) out[3 * fine.control(i, j) + c] = Q(i, j);
    }
  }
  return out;
}

}  // namespace sim_hw::spline_shell
