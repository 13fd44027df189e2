#include "twin/solvers/equilibrium_sensitivity.h"

#include <cmath>
#include <random>
#include <string>

#include <fmt/format.h>

#include "twin/solvers/newton_solver.h"
#include "twin/solvers/static_solver.h"

namespace twin {
namespace {

void require_sizes(const ShellModel& model, const DofMap& dofs, const VecX& x, const char* what) {
  const int n = model.vertex_count();
  if (dofs.vertex_count() != n || x.size() != 3 * static_cast<Eigen::Index>(n)) {
    throw std::invalid_argument(std::string(what) + ": expected a DofMap of " + std::to_string(n) +
                                " vertices and positions of size " + std::to_string(3 * n) +
                                ", got " + std::to_string(dofs.vertex_count()) + " and " +
                                std::to_string(x.size()));
  }
}

void require_relative_step(double relative_step, const char* what) {
  if (!(std::isfinite(relative_step) && relative_step > 0.0 && relative_step < 0.5)) {
    throw std::invalid_argument(std::string(what) + ": relative step must be in (0, 0.5), got " +
                                std::to_string(relative_step));
  }
}

// The arguments of the constructor, checked before anything is built from them.
const DofMap& checked(const ShellModel& model, const DofMap& dofs, const VecX& x,
                      double relative_step) {
  require_sizes(model, dofs, x, "EquilibriumSensitivity");
  require_relative_step(relative_step, "EquilibriumSensitivity");
  if (dofs.free_vertex_count() == 0) {
    throw std::invalid_argument("EquilibriumSensitivity: every vertex is held; nothing can move");
  }
  return dofs;
}

// Puts the model's material back when it goes out of scope, also during stack unwinding. The
// saved material was accepted by set_material before, so restoring it cannot throw.
class MaterialRestorer {
 public:
  explicit MaterialRestorer(ShellModel& model) : model_(model), saved_(model.material()) {}
  ~MaterialRestorer() { model_.set_material(saved_); }
  MaterialRestorer(const MaterialRestorer&) = delete;
  MaterialRestorer& operator=(const MaterialRestorer&) = delete;
  const Material& saved() const { return saved_; }

 private:
  ShellModel& model_;
  const Material saved_;
};

void zero_held(const DofMap& dofs, VecX& v) {
  for (int i = 0; i < dofs.vertex_count(); ++i) {
    if (dofs.is_fixed(i)) v.segment<3>(3 * i).setZero();
  }
}

// Upper bound of the largest eigenvalue (Gershgorin: the largest absolute row sum) of the
// symmetric matrix whose upper triangle is stored.
double gershgorin_bound(const HessianPattern::Matrix& upper) {
  VecX row_sum = VecX::Zero(upper.rows());
  for (int j = 0; j < upper.outerSize(); ++j) {
    for (HessianPattern::Matrix::InnerIterator it(upper, j); it; ++it) {
      row_sum(it.row()) += std::abs(it.value());
      if (it.row() != j) row_sum(j) += std::abs(it.value());
    }
  }
  return row_sum.size() > 0 ? row_sum.maxCoeff() : 0.0;
}

}  // namespace

VecX force_parameter_derivative(ShellModel& model, const DofMap& dofs, const VecX& x,
                                MaterialParameter parameter, double relative_step) {
  require_sizes(model, dofs, x, "force_parameter_derivative");
  require_relative_step(relative_step, "force_parameter_derivative");
  const Objective objective(model.potential_terms());
  MaterialRestorer restorer(model);
  Material plus = restorer.saved(), minus = restorer.saved();
  const ParameterScale scale = parameter_scale(parameter);
  const double p = get_parameter(minus, parameter);
  // The two sides of the difference, as each kind of parameter needs them.
  double up = p, down = p;
  if (scale.logarithmic) {
    up = p * (1.0 + relative_step);
    down = p * (1.0 - relative_step);
  } else if (parameter == MaterialParameter::kClampSlipCompliance) {
    // The slip springs go as 1 / (c + c0) with c0 1e-5 of the parameter's scale: a
    // forward step relative to c + c0 keeps the difference's error at O(step).
    up = p + relative_step * (p + ClampSlipTerm::kRigidJawCompliance_m_N);
  } else {
    // Effect parameters may sit at their bound (0: the effect absent), where a central
    // difference would step out of the valid range. Their energies are linear in them
    // (model_effects.h), so a forward difference of one scale step is exact up to rounding.
    up = p + relative_step * scale.scale;
  }
  // One rule for every kind: a side that would leave the parameter's range (a value the search
  // has taken to its bound: a grip width of 15 cm, a relaxation fraction of 0.95) is the value
  // itself, and a forward difference at the upper bound steps backward instead.
  if (up > scale.upper) {
    if (down == p) down = p - (up - p);
    up = p;
  }
  if (down < scale.lower) down = p;
  set_parameter(plus, parameter, up);
  set_parameter(minus, parameter, down);
  // The step actually taken, after rounding.
  const double step = get_parameter(plus, parameter) - get_parameter(minus, parameter);
  VecX g_plus, g_minus;
  model.set_material(plus);
  objective.evaluate(x, &g_plus, nullptr, HessianMode::kExact);
  model.set_material(minus);
  objective.evaluate(x, &g_minus, nullptr, HessianMode::kExact);
  VecX derivative = (g_plus - g_minus) / step;
  zero_held(dofs, derivative);
  return derivative;
}

EquilibriumSensitivity::EquilibriumSensitivity(ShellModel& model, const DofMap& dofs,
                                               const VecX& x, double relative_step)
    : model_(model),
      dofs_(checked(model, dofs, x, relative_step)),
      relative_step_(relative_step),
      objective_(model.potential_terms()),
      pattern_(dofs_, objective_.stencils()) {
  cholesky_.analyze(pattern_.matrix());
  update(x);
}

void EquilibriumSensitivity::update(const VecX& x) {
  require_sizes(model_, dofs_, x, "EquilibriumSensitivity::update");
  x_ = x;
  VecX g;
  objective_.evaluate(x_, &g, &pattern_, HessianMode::kExact);
  const double weight_N = free_weight_N(model_, dofs_);
  residual_ = gather_free(dofs_, g).norm() / (weight_N > 0.0 ? weight_N : 1.0);
  factorize();
}

void EquilibriumSensitivity::factorize() {
  const int nf = dofs_.free_dof_count();
  const std::string context = fmt::format(
      "equilibrium sensitivity: the exact Hessian of the potential over {} free DOFs ({} held "
      "vertices) at x (equilibrium residual {:.2e})",
      nf, dofs_.vertex_count() - dofs_.free_vertex_count(), residual_);
  relative_smallest_eigenvalue_ = 0.0;
  if (!cholesky_.factorize(pattern_.matrix())) {
    throw NotPositiveDefiniteError(
        context + " is not positive definite: x is not a stable equilibrium (a saddle, or a "
                  "state that is not an equilibrium), or the held vertices do not stop rigid "
                  "motion of the sheet");
  }
  // A singular K (rigid motion left free) can pass the factorisation when rounding makes its
  // zero pivots positive. Two steps of inverse iteration from a fixed pseudo-random start bound
  // the smallest eigenvalue from above (1 / ||K^-1 z|| for a unit z); that is compared with
  // Gershgorin's bound of the largest. Costs two solves, a few percent of the factorisation.
  VecX z(nf);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 0; i < nf; ++i) z(i) = uniform(rng);
  double inverse_norm = 0.0;
  for (int k = 0; k < 2; ++k) {
    z.normalize();
    z = cholesky_.solve(z);
    inverse_norm = z.norm();
  }
  const double ratio = 1.0 / (inverse_norm * gershgorin_bound(pattern_.matrix()));
  if (!(ratio > kSingularBelow)) {
    throw NotPositiveDefiniteError(fmt::format(
        "{} is not positive definite but numerically singular (smallest eigenvalue at most {:.1e} "
        "of the largest, expected above {:.0e}): the held vertices do not stop rigid motion of "
        "the sheet",
        context, ratio, kSingularBelow));
  }
  relative_smallest_eigenvalue_ = ratio;
  material_ = model_.material();
  stiffness_factor_ = model_.stiffness_factor();
}

VecX EquilibriumSensitivity::solve(const VecX& rhs) const {
  if (relative_smallest_eigenvalue_ <= 0.0) {
    throw std::logic_error(
        "EquilibriumSensitivity::solve: the last update failed; there is no factorisation");
  }
  if (rhs.size() != x_.size()) {
    throw std::invalid_argument("EquilibriumSensitivity::solve: expected a vector of size " +
                                std::to_string(x_.size()) + ", got " + std::to_string(rhs.size()));
  }
  const VecX free = cholesky_.solve(gather_free(dofs_, rhs));
  VecX out = VecX::Zero(x_.size());
  for (int v = 0; v < dofs_.vertex_count(); ++v) {
    const int f = dofs_.free_index(v);
    if (f >= 0) out.segment<3>(3 * v) = free.segment<3>(3 * f);
  }
  return out;
}

VecX EquilibriumSensitivity::force_derivative(MaterialParameter parameter) {
  if (!factorized_for(model_.material())) {
    throw std::logic_error(
        "EquilibriumSensitivity: the model's material or load age changed since K was factorised "
        "(or the last update failed); solve the new equilibrium and call update() first");
  }
  return force_parameter_derivative(model_, dofs_, x_, parameter, relative_step_);
}

bool EquilibriumSensitivity::factorized_for(const Material& m) const {
  if (relative_smallest_eigenvalue_ <= 0.0) return false;
  // The load age scales the stiffnesses of a relaxing material like a material change would.
  if (model_.stiffness_factor() != stiffness_factor_) return false;
  for (MaterialParameter p : kAllMaterialParameters) {
    if (get_parameter(m, p) != get_parameter(material_, p)) return false;
  }
  return m.poisson_ratio == material_.poisson_ratio;
}

VecX EquilibriumSensitivity::coordinate_scales(
    const std::vector<MaterialParameter>& parameters) const {
  VecX scales(parameters.size());
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    scales(j) = value_per_search_coordinate(
        parameters[j], get_parameter(model_.material(), parameters[j]));
  }
  return scales;
}

Eigen::MatrixXd EquilibriumSensitivity::tangents(
    const std::vector<MaterialParameter>& parameters) {
  Eigen::MatrixXd out(x_.size(), parameters.size());
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    out.col(j) = -solve(force_derivative(parameters[j]));
  }
  return out;
}

Eigen::MatrixXd EquilibriumSensitivity::coordinate_tangents(
    const std::vector<MaterialParameter>& parameters) {
  return tangents(parameters) * coordinate_scales(parameters).asDiagonal();
}

VecX EquilibriumSensitivity::adjoint_gradient(const VecX& dJ_dx,
                                              const std::vector<MaterialParameter>& parameters) {
  const VecX lambda = solve(dJ_dx);
  VecX out(parameters.size());
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    out(j) = -lambda.dot(force_derivative(parameters[j]));
  }
  return out;
}

VecX EquilibriumSensitivity::coordinate_adjoint_gradient(
    const VecX& dJ_dx, const std::vector<MaterialParameter>& parameters) {
  return adjoint_gradient(dJ_dx, parameters).cwiseProduct(coordinate_scales(parameters));
}

}  // namespace twin
