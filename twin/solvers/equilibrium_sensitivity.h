#pragma once
// Derivatives of a static equilibrium with respect to material parameters, for identifying the
// material from scanned marker positions.
//
// At an equilibrium x(p) the free part of the energy gradient vanishes: g_f(x(p), p) = 0.
// Differentiating, K dx_f/dp = -dg_f/dp, with K = d g_f / d x_f the exact Hessian of the
// potential (membrane + bending + gravity) over the free DOFs. K is factorised once per
// equilibrium and then serves
//   - forward tangents dx/dp_i = -K^-1 dg/dp_i, one solve per parameter (Gauss-Newton, Fisher
//     covariance of the estimate), and
//   - adjoint gradients of a scalar J(x): K lambda = dJ/dx, one solve for any number of
//     parameters, dJ/dp_i = -lambda^T dg/dp_i (K is symmetric, so K^T lambda = K lambda).
// Held (clamped) vertices do not move with p: their rows of dx/dp are zero. J may not depend on
// p except through x.
//
// dg/dp_i is a central difference of the exact gradient at fixed x in p_i, with a relative step:
// every energy is linear in the stiffnesses and the density (membrane in C, and C in G and in
// Y_u, Y_v scaled together; hinge stiffnesses in D_u, D_v; gravity in rho), so the difference
// is exact up to rounding whatever the step. Only Y_u or Y_v alone enter C nonlinearly (through
// 1 / (1 - nu^2 Y_v / Y_u)); there the error is O(step^2), about 1e-9 relative at the default.
//
// The paired parameters kTensile and kBending are differentiated along a scaling of both
// directions together (scale_parameter), per unit of the u value. On an isotropic sheet this is
// the derivative with respect to the common value. The coordinate versions, d/dy = (dp/dy) d/dp
// with y the search coordinate (log p, or p / scale for effect parameters), are what an
// optimiser working in those coordinates wants. Effect parameters (model_effects.h) enter
// their energies linearly and are differenced forward by relative_step times their scale; the
// clamp slip compliance, which does not, by relative_step times c + c0 (clamp_slip_term.h).
//
// Not thread-safe with other users of the model: computing dg/dp sets the model's material to
// the perturbed values and back (restored also when an exception passes through).

#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "twin/model/dof_map.h"
#include "twin/model/hessian_pattern.h"
#include "twin/model/material_parameters.h"
#include "twin/model/objective.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/sparse_cholesky.h"

namespace twin {

// The exact Hessian at x is not positive definite (or numerically singular): x is not a stable
// equilibrium, or the held vertices do not stop rigid motion of the sheet.
class NotPositiveDefiniteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Relative step of the dg/dp central difference (see above for why it hardly matters).
inline constexpr double kDefaultParameterStep = 1e-4;

// dg/dp (N per unit of p) at fixed positions x (3n, m): the free part of the derivative of the
// energy gradient, as a 3n vector with zeros at held vertices. The model's material is the same
// on return (or when this throws; std::invalid_argument if a perturbed material is invalid).
VecX force_parameter_derivative(ShellModel& model, const DofMap& dofs, const VecX& x,
                                MaterialParameter parameter,
                                double relative_step = kDefaultParameterStep);

class EquilibriumSensitivity {
 public:
  // Factorises the exact Hessian at x over the free DOFs of `dofs` (held vertices = clamped
  // ones). x should be an equilibrium of the model's current material (see residual()). Throws
  // std::invalid_argument for sizes that do not match the model, NotPositiveDefiniteError when
  // K is not positive definite. Keeps a reference to the model.
  EquilibriumSensitivity(ShellModel& model, const DofMap& dofs, const VecX& x,
                         double relative_step = kDefaultParameterStep);

  // Refactorises at a new equilibrium x (same held vertices; the material may have changed
  // through model.set_material), reusing the sparsity analysis. Same exceptions; after a throw,
  // solve() and the derivatives throw std::logic_error until an update succeeds.
  void update(const VecX& x);

  // ||free part of the energy gradient|| / ||weight on the free vertices|| at x: how far x is
  // from equilibrium, in the units of the static solver's residual tolerance (N without gravity).
  // The derivatives assume it is near zero.
  double residual() const { return residual_; }
  const VecX& position() const { return x_; }
  const DofMap& dofs() const { return dofs_; }
  // Estimate (upper bound) of K's smallest eigenvalue over a bound of its largest; below
  // kSingularBelow K counts as singular.
  double relative_smallest_eigenvalue() const { return relative_smallest_eigenvalue_; }
  static constexpr double kSingularBelow = 1e-13;

  // K^-1 applied to the free part of rhs (3n); the result is 3n with zeros at held vertices.
  VecX solve(const VecX& rhs) const;

  // The functions below need the model's material to be the one K was factorised for; they
  // throw std::logic_error if it has changed without update().

  // dg/dp at the factorised x (see force_parameter_derivative).
  VecX force_derivative(MaterialParameter parameter);

  // dx/dp_j (m per unit of p_j) in column j, 3n x P, zero rows at held vertices.
  Eigen::MatrixXd tangents(const std::vector<MaterialParameter>& parameters);
  // dx/dy_j = (dp_j/dy_j) dx/dp_j (m), y the search coordinates (material_parameters.h):
  // p_j dx/dp_j for a logarithmic parameter.
  Eigen::MatrixXd coordinate_tangents(const std::vector<MaterialParameter>& parameters);

  // dJ/dp_j for a scalar J(x) with gradient dJ_dx (3n; entries of held vertices are ignored),
  // by one adjoint solve.
  VecX adjoint_gradient(const VecX& dJ_dx, const std::vector<MaterialParameter>& parameters);
  // dJ/dy_j = (dp_j/dy_j) dJ/dp_j.
  VecX coordinate_adjoint_gradient(const VecX& dJ_dx, const std::vector<MaterialParameter>& parameters);

 private:
  void factorize();
  bool factorized_for(const Material& material) const;
  VecX coordinate_scales(const std::vector<MaterialParameter>& parameters) const;  // dp/dy

  ShellModel& model_;
  DofMap dofs_;
  double relative_step_;
  Objective objective_;
  HessianPattern pattern_;
  SparseCholesky cholesky_;
  VecX x_;
  double residual_ = 0.0;
  double relative_smallest_eigenvalue_ = 0.0;  // 0 while there is no valid factorisation
  Material material_;                         // the model's material when K was factorised
  double stiffness_factor_ = 1.0;             // and its relaxation factor at the model's load age
};

}  // namespace twin
