// Where the floor of issue 2's speed targets lies for this model, measured (not a test).
//
// It prints the static solve first (part 2 below), since part 1 factorises the Hessian at the
// hanging equilibrium that solve reaches.
//
// Part 1, the implicit step: a linearized backward-Euler step needs the Hessian factorised
// (nearly) afresh each step (twin_preconditioner_study shows why). This part factorises the
// benchmark sheet's step Hessian (hanging equilibrium, inertia of a 10 ms step) with every
// fill-reducing ordering CHOLMOD offers, on the scalar matrix and on the vertex graph (3x3
// blocks kept together), and with looser supernode amalgamation, and prints the flops, the time
// and the rate. Whatever the ordering, the factorisation alone is the floor of a direct step.
//
// Part 2, static equilibrium from flat: the Newton solve's iterations by phase (residual over
// 100 weights, 1-100, under 1) show where the time goes; then the same problem solved with
// Newton for the first iterations, limited-memory BFGS preconditioned by a factor of the
// projected Hessian renewed every `--refresh` iterations for the slow middle phase, and Newton
// again to finish: a cheaper iteration, to see whether the middle phase is a cost of Newton or
// of the problem.
//
// Usage: twin_solver_limits [--triangles 6000] [--newton-first 10] [--refresh 20] [--memory 10]

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <deque>
#include <dlfcn.h>
#include <omp.h>
#include <vector>

#include <Eigen/CholmodSupport>
#include <fmt/format.h>

#include "twin/bench/benchmark_sheet.h"
#include "twin/model/hessian_pattern.h"
#include "twin/model/inertia_term.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/objective.h"
#include "twin/solvers/sparse_cholesky.h"
#include "twin/solvers/static_solver.h"

namespace {

using namespace twin;
using Matrix = HessianPattern::Matrix;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void set_blas_threads(int threads) {
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(threads);
}

struct FactorTiming {
  double mflop = 0.0, factor_nonzeros = 0.0, ms = 0.0;
};

// Analyse `upper` with `ordering` (or the given permutation), then time 10 numeric
// factorisations, CHOLMOD's internal OpenMP loops kept serial as in sparse_cholesky.cc.
FactorTiming time_factorisation(Matrix& upper, int ordering, const std::vector<int>* permutation,
                                double relax_scale) {
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.nmethods = 1;
  common.method[0].ordering = permutation ? CHOLMOD_GIVEN : ordering;
  common.supernodal = CHOLMOD_SUPERNODAL;
  for (int i = 0; i < 3; ++i) common.nrelax[i] = static_cast<size_t>(relax_scale * common.nrelax[i]);
  cholmod_sparse a = Eigen::viewAsCholmod(upper);
  a.stype = 1;
  cholmod_factor* factor =
      cholmod_analyze_p(&a, permutation ? const_cast<int*>(permutation->data()) : nullptr, nullptr, 0, &common);
  const int saved_levels = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
  cholmod_factorize(&a, factor, &common);  // warm-up
  constexpr int kRepeats = 10;
  const auto start = Clock::now();
  for (int i = 0; i < kRepeats; ++i) cholmod_factorize(&a, factor, &common);
  FactorTiming timing{1e-6 * common.fl, common.lnz, 1e3 * seconds_since(start) / kRepeats};
  omp_set_max_active_levels(saved_levels);
  if (common.status != CHOLMOD_OK) timing.ms = NAN;
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  return timing;
}

// A fill-reducing ordering of the vertex graph (free vertices), expanded to their 3 DOFs. Free
// vertex f owns DOFs 3f..3f+2 (dof_map.h), so DOF row / 3 is its vertex.
std::vector<int> vertex_graph_ordering(const Matrix& upper) {
  const int vertices = static_cast<int>(upper.cols()) / 3;
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < upper.outerSize(); ++j) {
    for (Matrix::InnerIterator it(upper, j); it; ++it) entries.emplace_back(it.row() / 3, j / 3, 1.0);
  }
  Matrix graph(vertices, vertices);
  graph.setFromTriplets(entries.begin(), entries.end(), [](double a, double) { return a; });
  cholmod_common common;
  cholmod_start(&common);
  cholmod_sparse g = Eigen::viewAsCholmod(graph);
  g.stype = 1;
  std::vector<int> vertex_order(vertices);
  cholmod_metis(&g, nullptr, 0, 1, vertex_order.data(), &common);
  cholmod_finish(&common);
  std::vector<int> order;
  for (int v : vertex_order) {
    for (int k = 0; k < 3; ++k) order.push_back(3 * v + k);
  }
  return order;
}

void print_factorisations(const bench::BenchmarkSheet& sheet, const VecX& hanging) {
  const DofMap dofs = sheet.model.hold_clamps(sheet.clamps, sheet.poses);
  InertiaTerm inertia(sheet.model.vertex_masses_kg(), 0.0);
  inertia.set_step(hanging, VecX::Zero(hanging.size()), 0.01);
  std::vector<const EnergyTerm*> terms = sheet.model.potential_terms();
  terms.push_back(&inertia);
  const Objective objective(terms);
  HessianPattern pattern(dofs, objective.stencils());
  objective.evaluate(hanging, nullptr, &pattern, HessianMode::kProjected);
  Matrix upper = pattern.matrix();
  const std::vector<int> by_vertex = vertex_graph_ordering(upper);
  fmt::print("step Hessian: {} free DOFs, {} stored non-zeros (upper triangle)\n", upper.cols(), upper.nonZeros());
  fmt::print("{:>13} {:<42} {:>8} {:>14} {:>10} {:>9}\n", "BLAS threads", "ordering", "MFlop",
             "factor nnz", "ms", "GFlop/s");
  auto row = [&](int blas, const char* name, const FactorTiming& t) {
    fmt::print("{:>13} {:<42} {:>8.1f} {:>14.0f} {:>10.2f} {:>9.1f}\n", blas, name, t.mflop, t.factor_nonzeros, t.ms,
               t.mflop / t.ms);
  };
  for (int blas : {1, 2}) {
    set_blas_threads(blas);
    row(blas, "nested dissection (CHOLMOD, the solver's)", time_factorisation(upper, CHOLMOD_NESDIS, nullptr, 1.0));
    if (blas == 2) continue;
    row(blas, "METIS", time_factorisation(upper, CHOLMOD_METIS, nullptr, 1.0));
    row(blas, "AMD", time_factorisation(upper, CHOLMOD_AMD, nullptr, 1.0));
    row(blas, "METIS on the vertex graph", time_factorisation(upper, 0, &by_vertex, 1.0));
    row(blas, "METIS, supernodes relaxed 2x", time_factorisation(upper, CHOLMOD_METIS, nullptr, 2.0));
    row(blas, "METIS, supernodes relaxed 4x", time_factorisation(upper, CHOLMOD_METIS, nullptr, 4.0));
  }
  set_blas_threads(1);
}

// The Newton solve from flat, its iterations counted by residual phase.
void print_newton_phases(const bench::BenchmarkSheet& sheet, VecX& hanging) {
  int phase[3] = {0, 0, 0};
  NewtonOptions options = default_static_options();
  options.on_iteration = [&](const NewtonIteration& it) {
    ++phase[it.residual > 100.0 ? 0 : it.residual >= 1.0 ? 1 : 2];
  };
  hanging = sheet.flat;
  StaticSolver statics(sheet.model);
  const auto start = Clock::now();
  const SolveReport report = statics.solve(sheet.clamps, sheet.poses, hanging, options);
  fmt::print("Newton from flat: {:.1f} ms, {} iterations ({} with residual > 100 weights, {} at 1-100, {} below 1), "
             "energy {:.6f} J, {}\n",
             1e3 * seconds_since(start), report.iterations, phase[0], phase[1], phase[2], report.energy_J,
             report.usable() ? "converged" : "FAILED");
}

// Newton for `newton_first` iterations, then preconditioned L-BFGS down to a residual of 0.3
// weights, then Newton to convergence.
void print_lbfgs_static(const bench::BenchmarkSheet& sheet, int newton_first, int refresh, int memory) {
  const ShellModel& model = sheet.model;
  VecX x = sheet.flat;
  const auto start = Clock::now();
  StaticSolver statics(model);
  NewtonOptions first = default_static_options();
  first.max_iterations = newton_first;
  first.accept_iteration_budget = true;
  const SolveReport opening = statics.solve(sheet.clamps, sheet.poses, x, first, StaticSolver::OnFailure::kGiveUp);
  const double opening_ms = 1e3 * seconds_since(start);

  const DofMap dofs = model.hold_clamps(sheet.clamps, sheet.poses);
  const double weight_N = free_weight_N(model, dofs);
  const Objective objective(model.potential_terms());
  HessianPattern pattern(dofs, objective.stencils());
  SparseCholesky factor;
  factor.analyze(pattern.matrix());
  VecX grad(x.size()), trial(x.size()), trial_grad(x.size());
  auto moved = [&](const VecX& d, double a, VecX& out) {
    out = x;
    for (int v = 0; v < dofs.vertex_count(); ++v) {
      const int f = dofs.free_index(v);
      if (f >= 0) out.segment<3>(3 * v) += a * d.segment<3>(3 * f);
    }
  };
  double energy = objective.evaluate(x, &grad, nullptr, HessianMode::kProjected);
  VecX g = gather_free(dofs, grad);
  std::deque<std::pair<VecX, VecX>> pairs;  // (s, y), oldest first
  int iterations = 0, factorisations = 0, evaluations = 1;
  const auto middle_start = Clock::now();
  bool failed = false;
  for (; iterations < 5000 && g.norm() / weight_N >= 0.3; ++iterations) {
    if (iterations % refresh == 0) {
      objective.evaluate(x, nullptr, &pattern, HessianMode::kProjected);
      ++factorisations;
      if (!factor.factorize(pattern.matrix())) {
        failed = true;
        break;
      }
      pairs.clear();
    }
    // Two-loop recursion with the factor as the initial inverse Hessian.
    VecX q = g;
    std::vector<double> alpha(pairs.size());
    for (int i = static_cast<int>(pairs.size()) - 1; i >= 0; --i) {
      alpha[i] = pairs[i].first.dot(q) / pairs[i].second.dot(pairs[i].first);
      q -= alpha[i] * pairs[i].second;
    }
    VecX d = factor.solve(q);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const double beta = pairs[i].second.dot(d) / pairs[i].second.dot(pairs[i].first);
      d += (alpha[i] - beta) * pairs[i].first;
    }
    d = -d;
    double slope = g.dot(d);
    if (!(slope < 0.0)) {
      pairs.clear();
      d = -factor.solve(g);
      slope = g.dot(d);
    }
    double largest = 0.0;
    for (int f = 0; f < dofs.free_vertex_count(); ++f) largest = std::max(largest, d.segment<3>(3 * f).norm());
    double a = largest > 0.05 ? 0.05 / largest : 1.0;  // the static solver's 5 cm cap
    double trial_energy = 0.0;
    for (int halvings = 0;; ++halvings) {
      moved(d, a, trial);
      trial_energy = objective.evaluate(trial, &trial_grad, nullptr, HessianMode::kProjected);
      ++evaluations;
      if (trial_energy <= energy + 1e-4 * a * slope + 1e-13 * std::abs(energy)) break;
      if (halvings == 40) {
        failed = true;
        break;
      }
      a *= 0.5;
    }
    if (failed) break;
    const VecX g_next = gather_free(dofs, trial_grad);
    VecX s = a * d, y = g_next - g;
    if (s.dot(y) > 1e-12 * s.norm() * y.norm()) {
      pairs.emplace_back(std::move(s), std::move(y));
      if (static_cast<int>(pairs.size()) > memory) pairs.pop_front();
    }
    x.swap(trial);
    energy = trial_energy;
    g = g_next;
  }
  const double middle_ms = 1e3 * seconds_since(middle_start);
  const auto finish_start = Clock::now();
  const SolveReport finish = failed ? SolveReport{} : statics.solve(sheet.clamps, sheet.poses, x,
                                                                     default_static_options(),
                                                                     StaticSolver::OnFailure::kGiveUp);
  fmt::print("Newton {} + L-BFGS + Newton: {:.1f} ms ({} Newton iterations {:.1f} ms; {} L-BFGS iterations, "
             "{} factorisations, {} energy evaluations {:.1f} ms; {} Newton iterations {:.1f} ms), energy {:.6f} J, "
             "{}\n",
             newton_first, 1e3 * seconds_since(start), opening.iterations, opening_ms, iterations, factorisations,
             evaluations, middle_ms, finish.iterations, 1e3 * seconds_since(finish_start), finish.energy_J,
             !failed && finish.usable() ? "converged" : "FAILED");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Where the floor of the implicit step and the static solve lies (issue 2)"};
  int triangles = 6000, newton_first = 10, refresh = 20, memory = 10;
  app.add_option("--triangles", triangles, "target triangle count");
  app.add_option("--newton-first", newton_first, "Newton iterations before L-BFGS")->check(CLI::Range(0, 200));
  app.add_option("--refresh", refresh, "L-BFGS iterations per new preconditioner factor")->check(CLI::Range(1, 1000));
  app.add_option("--memory", memory, "L-BFGS pairs kept")->check(CLI::Range(0, 100));
  CLI11_PARSE(app, argc, argv);

  const bench::BenchmarkSheet sheet(triangles);
  fmt::print("solver limits: {} triangles, {} vertices, {} OpenMP threads\n", sheet.model.mesh().triangle_count(),
             sheet.model.vertex_count(), omp_get_max_threads());
  VecX hanging;
  print_newton_phases(sheet, hanging);
  print_lbfgs_static(sheet, newton_first, refresh, memory);
  print_factorisations(sheet, hanging);
  return 0;
}
