#include "sim_hw/real_sheet/equilibrium_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "sim_hw/real_sheet/damped_newton.h"

namespace sim_hw::real_sheet {
namespace {

// The jaws after a step of alpha along dx's rotation part.
std::vector<JawHold> turned(const std::vector<JawHold>& jaws, const VecX& dx, int nodes, double alpha) {
  std::vector<JawHold> out = jaws;
  int pivot = nodes;
  for (JawHold& j : out) {
    if (j.pad.kind != JawKind::kPivot) continue;
    j.rotation = rotation_exp(alpha * dx.segment<3>(3 * pivot)) * j.rotation;
    ++pivot;
  }
  return out;
}

}  // namespace

SolveWorkspace::SolveWorkspace() : cholesky_(std::make_unique<Cholesky>()) {}
SolveWorkspace::~SolveWorkspace() = default;

BlockSparseMatrix& SolveWorkspace::pattern(const SheetModel& model, const std::vector<JawHold>& jaws) {
  std::vector<std::vector<int>> key;
  for (const JawHold& j : jaws) {
    key.push_back(pad_nodes(j.pad));
    key.back().push_back(j.pad.kind == JawKind::kPivot ? -1 : -2);
  }
  if (!built_ || key != key_) {
    pattern_ = model.hessian_pattern(jaws);
    key_ = std::move(key);
    built_ = true;
  }
  return pattern_;
}

namespace {

// The plate and its jaws as the damped Newton method sees them: node positions, then the pivot
// jaws' turns, which move multiplicatively.
class SheetProblem final : public NewtonProblem {
 public:
  SheetProblem(const SheetModel& model, VecX& x, std::vector<JawHold>& jaws, const StepTerms* step)
      : model_(model), x_(x), jaws_(jaws), step_(step), n_(model.node_count()) {}

  double energy_at(const VecX* dx, double alpha, VecX* g) const override {
    if (!dx) return model_.energy(x_, jaws_, g, nullptr, Hessian::kExact, step_);
    const VecX x = x_ + alpha * dx->head(3 * n_);
    return model_.energy(x, turned(jaws_, *dx, n_, alpha), g, nullptr, Hessian::kExact, step_);
  }
  void hessian(BlockSparseMatrix& H, Hessian kind) const override {
    model_.energy(x_, jaws_, nullptr, &H, kind, step_);
  }
  void move(const VecX& dx, double alpha) override {
    x_ = x_ + alpha * dx.head(3 * n_);
    jaws_ = turned(jaws_, dx, n_, alpha);
  }
  double longest_move_m(const VecX& dx) const override { return dx.head(3 * n_).lpNorm<Eigen::Infinity>(); }
  void save() override { x_saved_ = x_, jaws_saved_ = jaws_; }
  void restore() override { x_ = x_saved_, jaws_ = jaws_saved_; }

 private:
  const SheetModel& model_;
  VecX& x_;
  std::vector<JawHold>& jaws_;
  const StepTerms* step_;
  int n_;
  VecX x_saved_;
  std::vector<JawHold> jaws_saved_;
};

}  // namespace

EquilibriumReport solve_equilibrium(const SheetModel& model, VecX& x, std::vector<JawHold>& jaws,
                                    const EquilibriumOptions& options, const StepTerms* step,
                                    SolveWorkspace* workspace) {
  const int n = model.node_count();
  // Damping metric: node masses; a pivot's turn weighs the pad's area moment of the sheet's
  // density (kg m^2), so mu M is a pseudo-time on both.
  const int dofs = model.dof_count(jaws);
  VecX metric(dofs);
  for (int i = 0; i < n; ++i) metric.segment<3>(3 * i).setConstant(model.node_mass_kg()[i]);
  {
    int pivot = n;
    for (const JawHold& j : jaws) {
      if (j.pad.kind != JawKind::kPivot) continue;
      double moment_m4 = 0;
      for (const JawSample& s : j.pad.samples) moment_m4 += s.area_m2 * s.offset_m.squaredNorm();
      metric.segment<3>(3 * pivot).setConstant(std::max(1e-12, model.material().density_kg_m2 * moment_m4));
      ++pivot;
    }
  }
  SolveWorkspace local;
  SolveWorkspace& work = workspace ? *workspace : local;
  DampedNewtonOptions newton;
  newton.tolerance_N = options.force_tolerance * model.total_weight_N();
  newton.step_tolerance_m = options.step_tolerance_m;
  newton.max_iterations = options.max_iterations;
  newton.initial_damping_1_s2 = options.initial_damping_1_s2;
  newton.keep_on_limit = options.keep_on_limit;
  newton.projected_hessian = options.projected_hessian;
  newton.step_limit_m = options.step_limit_m;
  newton.trace = std::getenv("REAL_SHEET_TRACE") != nullptr;
  SheetProblem problem(model, x, jaws, step);
  const DampedNewtonReport r = damped_newton(problem, work.pattern(model, jaws), work.cholesky(), metric, newton);
  EquilibriumReport report;
  report.converged = r.converged;
  report.budget_used = r.budget_used;
  report.iterations = r.iterations;
  report.factorizations = r.factorizations;
  report.max_force_N = r.max_force_N;
  report.energy_J = r.energy_J;
  report.message = r.message;
  return report;
}

}  // namespace sim_hw::real_sheet
