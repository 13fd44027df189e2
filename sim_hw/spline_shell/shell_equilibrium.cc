#include "sim_hw/spline_shell/shell_equilibrium.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "sim_hw/real_sheet/cholesky.h"
#include "sim_hw/spline_shell/jaw_grip.h"
#include "sim_hw/spline_shell/preconditioned_lbfgs.h"

namespace sim_hw::spline_shell {

std::vector<int> fixed_controls(const ShellModel& model, const ShellHolds& holds) {
  std::vector<int> fixed = holds.fixed_controls;
  if (jaw_grip(model.material()).fixes_controls()) {
    for (const JawHold& h : holds.jaws) {
      const std::vector<int> held = held_controls(model.patch(), h.jaw);
      fixed.insert(fixed.end(), held.begin(), held.end());
    }
  }
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  return fixed;
}

std::vector<int> apply_holds(const ShellModel& model, const ShellHolds& holds, VecX& x) {
  // Slipping jaws' controls are placed too (the rigid motion is their predictor) but left free.
  for (const JawHold& h : holds.jaws) {
    place_held_controls(model.patch(), h.jaw, held_controls(model.patch(), h.jaw), h.centre_m, h.rotation, x);
  }
  return fixed_controls(model, holds);
}

double holds_energy(const ShellModel& model, const ShellHolds& holds, const VecX& x, VecX* gradient,
                    BlockSparseMatrix* hessian) {
  const JawGrip grip = jaw_grip(model.material());
  double energy = 0;
  for (const JawHold& h : holds.jaws) {
    energy += grip_energy(model.patch(), grip, h.jaw, h.centre_m, h.rotation, x, gradient, hessian);
  }
  return energy;
}

Vec3 holding_force_N(const ShellModel& model, const ShellHolds& holds, const VecX& x) {
  // On a fixed control the jaw's reaction balances the shell's and the springs' gradients; on
  // every control the springs pull with minus theirs: the springs' share on fixed controls cancels.
  std::vector<char> fixed(model.patch().control_count(), 0);
  for (int c : fixed_controls(model, holds)) fixed[c] = 1;
  VecX g = VecX::Zero(model.dof_count()), springs = VecX::Zero(model.dof_count());
  model.energy(x, &g, nullptr);
  holds_energy(model, holds, x, &springs, nullptr);
  Vec3 f = Vec3::Zero();
  for (int c = 0; c < model.patch().control_count(); ++c) {
    f += fixed[c] ? Vec3(g.segment<3>(3 * c)) : Vec3(-springs.segment<3>(3 * c));
  }
  return f;
}

double lowest_eigenvalue_1_s2(const ShellModel& model, const ShellHolds& holds, const VecX& x, int iterations) {
  std::vector<char> fixed(model.patch().control_count(), 0);
  for (int c : fixed_controls(model, holds)) fixed[c] = 1;  // placed where the solve put them
  BlockSparseMatrix H = model.hessian_pattern();
  model.energy(x, nullptr, &H, Hessian::kExact);
  holds_energy(model, holds, x, nullptr, &H);
  H.fix_blocks(fixed);
  real_sheet::Cholesky cholesky;
  if (!cholesky.factorize(H)) return std::numeric_limits<double>::quiet_NaN();
  VecX m(model.dof_count());
  for (int c = 0; c < model.patch().control_count(); ++c) m.segment<3>(3 * c).setConstant(fixed[c] ? 0.0 : model.control_mass_kg()[c]);
  // Inverse iteration v <- H^-1 M v from a fixed, rough start; lambda = v.Mv / v.M H^-1 M v.
  VecX v = VecX::Ones(model.dof_count());
  for (int i = 0; i < v.size(); ++i) v[i] += 0.5 * std::sin(1.7 * i);
  double lambda = 0;
  for (int k = 0; k < iterations; ++k) {
    const VecX Mv = m.cwiseProduct(v);
    const VecX w = cholesky.solve(Mv);
    lambda = v.dot(Mv) / w.dot(Mv);
    v = w / std::sqrt(w.dot(m.cwiseProduct(w)));
  }
  return lambda;
}

namespace {

// The shell with its held controls as fixed unknowns: their gradient is zero and their rows of
// the Hessian the identity's, so no step moves them.
class HeldShell final : public real_sheet::NewtonProblem {
 public:
  HeldShell(const ShellModel& model, const ShellHolds& holds, std::vector<char> fixed, VecX& x)
      : model_(model), holds_(holds), fixed_(std::move(fixed)), x_(x) {}
  double energy_at(const VecX* dx, double alpha, VecX* g) const override {
    if (g) *g = VecX::Zero(model_.dof_count());
    const VecX moved = dx ? VecX(x_ + alpha * *dx) : VecX();
    const VecX& at = dx ? moved : x_;
    const double e = model_.energy(at, g, nullptr) + holds_energy(model_, holds_, at, g, nullptr);
    if (g) {
      for (std::size_t c = 0; c < fixed_.size(); ++c) {
        if (fixed_[c]) g->segment<3>(3 * c).setZero();
      }
    }
    return e;
  }
  void hessian(BlockSparseMatrix& H, Hessian kind) const override {
    H.set_zero();
    model_.energy(x_, nullptr, &H, kind);
    holds_energy(model_, holds_, x_, nullptr, &H);
    H.fix_blocks(fixed_);
  }
  void move(const VecX& dx, double alpha) override { x_ = x_ + alpha * dx; }
  double longest_move_m(const VecX& dx) const override { return dx.lpNorm<Eigen::Infinity>(); }
  void save() override { saved_ = x_; }
  void restore() override { x_ = saved_; }

 private:
  const ShellModel& model_;
  const ShellHolds& holds_;
  std::vector<char> fixed_;
  VecX& x_;
  VecX saved_;
};

}  // namespace

ShellSolveReport solve_shell(const ShellModel& model, const ShellHolds& holds, VecX& x, const ShellSolveOptions& options) {
  const VecX x_start = x;
  std::vector<char> fixed(model.patch().control_count(), 0);
  for (int c : apply_holds(model, holds, x)) fixed[c] = 1;
  VecX metric(model.dof_count());
  for (int c = 0; c < model.patch().control_count(); ++c) {
    metric.segment<3>(3 * c).setConstant(std::max(model.control_mass_kg()[c], 1e-12));
  }
  BlockSparseMatrix H = model.hessian_pattern();
  real_sheet::Cholesky cholesky;
  real_sheet::DampedNewtonOptions newton;
  newton.tolerance_N = options.force_tolerance * model.total_weight_N();
  newton.step_tolerance_m = options.step_tolerance_m;
  newton.max_iterations = options.max_iterations;
  newton.initial_damping_1_s2 = options.initial_damping_1_s2;
  newton.step_limit_m = options.step_limit_m;
  newton.shifted_exact = true;
  newton.trace = options.trace || std::getenv("SPLINE_SHELL_TRACE") != nullptr;
  HeldShell problem(model, holds, std::move(fixed), x);
  ShellSolveReport report;
  if (options.relax_to_force > 0 && options.initial_damping_1_s2 == 0) {
    LbfgsOptions relax;
    relax.tolerance_N = std::max(newton.tolerance_N, options.relax_to_force * model.total_weight_N());
    relax.trace = newton.trace;
    const LbfgsReport relaxed = preconditioned_lbfgs(problem, H, cholesky, metric, relax);
    report.relaxation_iterations = relaxed.iterations;
    report.factorizations = relaxed.factorizations;
  }
  const int relaxation_factorizations = report.factorizations;
  static_cast<real_sheet::DampedNewtonReport&>(report) = real_sheet::damped_newton(problem, H, cholesky, metric, newton);
  report.factorizations += relaxation_factorizations;
  if (!report.converged && !report.budget_used) x = x_start;  // the jaws' placement too
  return report;
}

}  // namespace sim_hw::spline_shell
