#include "sim_hw/spline_shell/shell_model.h"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/real_sheet/kirchhoff_love_point.h"

namespace sim_hw::spline_shell {
namespace {

using real_sheet::Mat15;
using real_sheet::Vec15;

// Rows of the point weights in the order of the bending kernel's y = (x_uu, x_vv, x_uv, x_u, x_v).
constexpr int kRows[5] = {kUU, kVV, kUV, kU, kV};

}  // namespace

ShellModel::ShellModel(SplinePatch patch, SheetMaterial material, std::vector<Vec2> marker_uv_m)
    : patch_(std::move(patch)),
      material_(std::move(material)),
      markers_(std::move(marker_uv_m)),
      age_s_(std::numeric_limits<double>::quiet_NaN()) {
  mass_kg_ = VecX::Zero(patch_.control_count());
  rest_k_.resize(patch_.element_count());
  for (int e = 0; e < patch_.element_count(); ++e) {
    const std::vector<int>& controls = patch_.element_controls(e);
    for (const QuadraturePoint& q : patch_.element_points(e)) {
      for (std::size_t k = 0; k < controls.size(); ++k) {
        mass_kg_[controls[k]] += material_.density_kg_m2 * q.area_m2 * q.w(kValue, k);
      }
      rest_k_[e].push_back(real_sheet::rest_curvature_at(material_, q.uv_m));
    }
  }
  for (std::size_t m = 0; m < markers_.size(); ++m) {
    const Vec2& uv = markers_[m];
    if (!(uv.x() >= 0 && uv.x() <= patch_.width_m() && uv.y() >= 0 && uv.y() <= patch_.height_m())) {
      throw std::invalid_argument(fmt::format("spline shell: marker {} at ({}, {}) m is off the {} x {} m sheet", m,
                                              uv.x(), uv.y(), patch_.width_m(), patch_.height_m()));
    }
    const PointWeights pw = patch_.weights_at(uv);
    for (std::size_t k = 0; k < pw.controls.size(); ++k) mass_kg_[pw.controls[k]] += material_.marker_mass_kg * pw.w(kValue, k);
  }
}

double ShellModel::total_weight_N() const { return mass_kg_.sum() * real_sheet::kGravity_m_s2; }

BlockSparseMatrix ShellModel::hessian_pattern() const {
  std::vector<std::vector<int>> groups;
  groups.reserve(patch_.element_count());
  for (int e = 0; e < patch_.element_count(); ++e) groups.push_back(patch_.element_controls(e));
  return BlockSparseMatrix(patch_.control_count(), groups);
}

double ShellModel::element_energy(int element, const VecX& x, bool membrane, bool bending, Eigen::VectorXd* g,
                                  Eigen::MatrixXd* H, Hessian kind) const {
  // Every element of an open tensor-product patch has (p + 1)^2 controls: the sizes are fixed
  // per degree, so the per-point products are fixed-size (several times faster than dynamic ones
  // at these sizes, where the element loop is most of a Newton iteration).
  switch (patch_.element_controls(element).size()) {
    case 9: return element_energy_n<9>(element, x, membrane, bending, g, H, kind);
    case 16: return element_energy_n<16>(element, x, membrane, bending, g, H, kind);
    case 25: return element_energy_n<25>(element, x, membrane, bending, g, H, kind);
    default: throw std::logic_error("spline shell: an element's control count is not (p + 1)^2 for p in 2..4");
  }
}

template <int N>
double ShellModel::element_energy_n(int element, const VecX& x, bool membrane, bool bending, Eigen::VectorXd* g,
                                    Eigen::MatrixXd* H, Hessian kind) const {
  using Weights = Eigen::Matrix<double, 5, N>;
  using Square = Eigen::Matrix<double, N, N>;
  const std::vector<int>& controls = patch_.element_controls(element);
  Eigen::Matrix<double, 3, N> P;
  for (int k = 0; k < N; ++k) P.col(k) = x.segment<3>(3 * controls[k]);
  const double creep = material_.creep_factor(age_s_);
  Eigen::Matrix3d C = material_.membrane_C_N_m;
  C(2, 2) *= creep;
  const Eigen::Matrix3d D = creep * material_.bending_D_Nm();
  Weights W;
  Eigen::Matrix<double, 3, N> G = Eigen::Matrix<double, 3, N>::Zero();
  // H_x(3s + a, 3t + b) = sum_q sum_{r, r'} W_q(r, s) Hy_q(3r + a, 3r' + b) W_q(r', t): per
  // coordinate pair (a, b) an N x N block, summed over the points and scattered once. Hy is
  // symmetric, so the (b, a) block is the (a, b) block's transpose.
  std::array<Square, 6> M;
  constexpr int kPairA[6] = {0, 0, 0, 1, 1, 2}, kPairB[6] = {0, 1, 2, 1, 2, 2};
  if (H) {
    for (Square& m : M) m.setZero();
  }
  double energy = 0;
  const std::vector<QuadraturePoint>& points = patch_.element_points(element);
  for (std::size_t qi = 0; qi < points.size(); ++qi) {
    const QuadraturePoint& q = points[qi];
    for (int r = 0; r < 5; ++r) W.row(r) = q.w.row(kRows[r]);
    const Eigen::Matrix<double, 3, 5> Y = P.lazyProduct(W.transpose());  // columns x_uu, x_vv, x_uv, x_u, x_v
    const Vec15 y = Eigen::Map<const Vec15>(Y.data());
    Vec15 gy = Vec15::Zero();
    Mat15 Hy = Mat15::Zero();
    if (bending) {
      Vec15 gb;
      Mat15 Hb;
      energy += q.area_m2 * real_sheet::kirchhoff_love_density(y, rest_k_[element][qi], D, material_.stiffening_m2,
                                                               g ? &gb : nullptr, H ? &Hb : nullptr, kind);
      if (g) gy += gb;
      if (H) Hy += Hb;
    }
    if (membrane) {
      Vec6 gm;
      Mat6 Hm;
      energy += q.area_m2 * membrane_density(y.tail<6>(), C, Eigen::Vector3d::Zero(), g ? &gm : nullptr,
                                             H ? &Hm : nullptr, kind);
      if (g) gy.tail<6>() += gm;
      if (H) Hy.bottomRightCorner<6, 6>() += Hm;
    }
    // dE/dP = sum_r gy_r W_r^T (3 x N).
    if (g) G.noalias() += (q.area_m2 * Eigen::Map<const Eigen::Matrix<double, 3, 5>>(gy.data())).lazyProduct(W);
    if (H) {
      for (int pair = 0; pair < 6; ++pair) {
        const int a = kPairA[pair], b = kPairB[pair];
        Eigen::Matrix<double, 5, 5> Hab;
        for (int r = 0; r < 5; ++r) {
          for (int s = 0; s < 5; ++s) Hab(r, s) = q.area_m2 * Hy(3 * r + a, 3 * s + b);
        }
        // Coefficient-wise products: Eigen would send these sizes to its blocked GEMM, whose
        // packing costs more than the arithmetic here.
        const Weights T = Hab.lazyProduct(W);
        M[pair].noalias() += W.transpose().lazyProduct(T);
      }
    }
  }
  if (g) *g = Eigen::Map<const Eigen::VectorXd>(G.data(), 3 * N);
  if (H) {
    H->resize(3 * N, 3 * N);
    for (int pair = 0; pair < 6; ++pair) {
      const int a = kPairA[pair], b = kPairB[pair];
      for (int t = 0; t < N; ++t) {
        for (int s = 0; s < N; ++s) {
          (*H)(3 * s + a, 3 * t + b) = M[pair](s, t);
          (*H)(3 * t + b, 3 * s + a) = M[pair](s, t);
        }
      }
    }
  }
  return energy;
}

double ShellModel::energy(const VecX& x, VecX* gradient, BlockSparseMatrix* hessian, Hessian kind) const {
  // Elements in colours: two elements of one colour share no control (their spans are p + 1
  // apart in u or in v), so a colour's elements add into the gradient and the Hessian at once.
  const int eu_count = patch_.u().element_count(), ev_count = patch_.v().element_count();
  const int stride = patch_.degree() + 1;
  double energy = 0;
  for (int colour = 0; colour < stride * stride; ++colour) {
    const int cu = colour % stride, cv = colour / stride;
    const int nu = (eu_count - cu + stride - 1) / stride, nv = (ev_count - cv + stride - 1) / stride;
    const int count = std::max(0, nu) * std::max(0, nv);
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : energy)
    for (int k = 0; k < count; ++k) {
      const int e = (cv + stride * (k / nu)) * eu_count + cu + stride * (k % nu);
      Eigen::VectorXd g;
      Eigen::MatrixXd H;
      energy += element_energy(e, x, true, true, gradient ? &g : nullptr, hessian ? &H : nullptr, kind);
      const std::vector<int>& controls = patch_.element_controls(e);
      if (gradient) {
        for (std::size_t j = 0; j < controls.size(); ++j) gradient->segment<3>(3 * controls[j]) += g.segment<3>(3 * j);
      }
      if (hessian) hessian->add(controls, H);
    }
  }
  for (int c = 0; c < patch_.control_count(); ++c) {
    const double weight_N = mass_kg_[c] * real_sheet::kGravity_m_s2;
    energy += weight_N * x[3 * c + 2];
    if (gradient) (*gradient)[3 * c + 2] += weight_N;
  }
  return energy;
}

double ShellModel::membrane_energy(const VecX& x) const {
  double energy = 0;
  for (int e = 0; e < patch_.element_count(); ++e) energy += element_energy(e, x, true, false, nullptr, nullptr, Hessian::kExact);
  return energy;
}

double ShellModel::bending_energy(const VecX& x) const {
  double energy = 0;
  for (int e = 0; e < patch_.element_count(); ++e) energy += element_energy(e, x, false, true, nullptr, nullptr, Hessian::kExact);
  return energy;
}

std::vector<Vec3> ShellModel::marker_positions(const VecX& x) const {
  std::vector<Vec3> out;
  out.reserve(markers_.size());
  for (const Vec2& uv : markers_) out.push_back(patch_.position(x, uv));
  return out;
}

}  // namespace sim_hw::spline_shell
