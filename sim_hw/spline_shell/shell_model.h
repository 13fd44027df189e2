#pragma once
// The reference sheet's total potential: a Kirchhoff-Love shell on a B-spline patch (Kiendl's
// isogeometric shell, on a flat rest state whose material coordinates are arc lengths), made of
// the independent lab's material (sim_hw/real_sheet/sheet_material.h: orthotropic
// St. Venant-Kirchhoff membrane, full bending matrix D11, D22, D12, D66, rest curvature and
// creases, stiffening, creep, marker masses), integrated by Gauss quadrature over every element:
//   membrane   sum_q A_q psi_m(x_u, x_v)                  (membrane_point.h)
//   bending    sum_q A_q psi_b(x_uu, x_vv, x_uv, x_u, x_v) (real_sheet/kirchhoff_love_point.h)
//   gravity    g sum_c m_c z_c, m_c = rho int N_c dA + the markers' masses by their basis weights
// (exact: the weight's potential is linear in the control points). Unknowns are the control
// points (3 per control, patch order); energy in J, gradient in N, Hessian in N/m. The jaws'
// holds fix control points (square_jaw.h, shell_equilibrium.h).

#include <vector>

#include <Eigen/Core>

#include "sim_hw/real_sheet/block_sparse.h"
#include "sim_hw/real_sheet/sheet_material.h"
#include "sim_hw/spline_shell/membrane_point.h"
#include "sim_hw/spline_shell/spline_patch.h"

namespace sim_hw::spline_shell {

using real_sheet::BlockSparseMatrix;
using real_sheet::SheetMaterial;

class ShellModel {
 public:
  // Throws std::invalid_argument for a marker off the sheet.
  ShellModel(SplinePatch patch, SheetMaterial material, std::vector<Vec2> marker_uv_m = {});

  const SplinePatch& patch() const { return patch_; }
  const SheetMaterial& material() const { return material_; }
  int dof_count() const { return 3 * patch_.control_count(); }
  // Creep: shear and bending at `age_s` after the clamps last moved (NaN: long after).
  void set_age_s(double age_s) { age_s_ = age_s; }
  double age_s() const { return age_s_; }

  // Per control point (kg): the share of the sheet's and the markers' mass whose weight it
  // carries (sums to the total mass; used as the solver's lumped mass too).
  const VecX& control_mass_kg() const { return mass_kg_; }
  double total_weight_N() const;

  // The pattern: every element's controls couple.
  BlockSparseMatrix hessian_pattern() const;
  // Energy (J); adds the gradient into `gradient` and the Hessian into `hessian` when non-null
  // (both must be sized and zeroed, or hold other terms, by the caller).
  double energy(const VecX& x, VecX* gradient, BlockSparseMatrix* hessian, Hessian kind = Hessian::kExact) const;
  // Membrane and bending parts alone (no gravity): for patch tests.
  double membrane_energy(const VecX& x) const;
  double bending_energy(const VecX& x) const;

  const std::vector<Vec2>& marker_uv_m() const { return markers_; }
  std::vector<Vec3> marker_positions(const VecX& x) const;

 private:
  double element_energy(int element, const VecX& x, bool membrane, bool bending, Eigen::VectorXd* g,
                        Eigen::MatrixXd* H, Hessian kind) const;
  template <int N>  // N = (p + 1)^2 controls per element
  double element_energy_n(int element, const VecX& x, bool membrane, bool bending, Eigen::VectorXd* g,
                          Eigen::MatrixXd* H, Hessian kind) const;

  SplinePatch patch_;
  SheetMaterial material_;
  std::vector<Vec2> markers_;
  double age_s_;
  VecX mass_kg_;
  std::vector<std::vector<Eigen::Vector3d>> rest_k_;  // per element, per quadrature point
};

}  // namespace sim_hw::spline_shell
