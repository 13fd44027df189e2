// Can a two-level preconditioner replace the moving sheet's factorisation (issue 37, item 2)?
//
// On the benchmark sheet (benchmark_sheet.h), stepped with linearized backward Euler while a
// clamp circles, this program takes one step's Hessian H (projected, inertia and viscosity
// included, over the free DOFs) and solves H z = r by CG with a two-level V-cycle as the
// preconditioner: a forward Gauss-Seidel sweep, a coarse-grid correction P Ac^-1 P^T on the
// residual, a backward sweep (so the cycle is symmetric). P interpolates displacements from a
// coarser mesh of the same sheet (each fine vertex from its host coarse triangle, barycentric;
// it reproduces every displacement affine in the material coordinates) and Ac = P^T H P, the
// Galerkin operator, is factorised. It prints the CG iterations to relative residuals of 1e-2
// and 1e-6, what each part costs, and the same with a coarse factor some steps old (the fine
// sweeps always on the current H), against one factorisation of H itself and CG without a
// preconditioner. (A step-old factor of H itself needs 5 iterations to 1e-2:
// twin_preconditioner_study.)
//
// Usage: twin_multilevel_study [--triangles 6000] [--step 30] [--coarsening 4,16] [--sweeps 1]

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "twin/bench/benchmark_sheet.h"
#include "twin/mesh/material_point.h"
#include "twin/model/hessian_pattern.h"
#include "twin/model/inertia_term.h"
#include "twin/model/objective.h"
#include "twin/model/viscosity_term.h"
#include "twin/solvers/sparse_cholesky.h"

namespace {

using namespace twin;
using Matrix = HessianPattern::Matrix;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return 1e3 * std::chrono::duration<double>(Clock::now() - start).count();
}

// The objective's projected Hessian at x over the free vertices (upper triangle).
Matrix hessian_at(const DofMap& dofs, const Objective& objective, const VecX& x) {
  HessianPattern pattern(dofs, objective.stencils());
  objective.evaluate(x, nullptr, &pattern, HessianMode::kProjected);
  return pattern.matrix();
}

// Displacement interpolation from `coarse` to the free vertices of the fine mesh: 3 rows per
// free fine vertex, 3 columns per coarse vertex, w I3 blocks.
Matrix prolongation(const SheetMesh& coarse, const SheetMesh& fine, const DofMap& dofs) {
  const MaterialPointMap on_coarse(coarse, fine.rest_uv);
  std::vector<Eigen::Triplet<double>> entries;
  for (int v = 0; v < fine.vertex_count(); ++v) {
    const int f = dofs.free_index(v);
    if (f < 0) continue;
    const MaterialPointLocation& at = on_coarse.location(v);
    for (int k = 0; k < 3; ++k) {
      if (at.weights(k) == 0.0) continue;
      for (int d = 0; d < 3; ++d) entries.emplace_back(3 * f + d, 3 * at.vertices[k] + d, at.weights(k));
    }
  }
  Matrix p(dofs.free_dof_count(), 3 * coarse.vertex_count());
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

// One level below the fine one: its interpolation and its factorised Galerkin operator.
struct CoarseLevel {
  Matrix p;
  SparseCholesky factor;
  double galerkin_ms = 0.0, factor_ms = 0.0;
  bool ok = false;
  void build(const Matrix& full_h) {
    const auto t0 = Clock::now();
    Matrix ac = Matrix(p.transpose() * full_h * p).triangularView<Eigen::Upper>();
    // Coarse vertices that interpolate to no free vertex (inside a clamp's patch): keep the
    // operator definite with a unit diagonal there.
    for (int j = 0; j < ac.cols(); ++j) {
      if (ac.coeff(j, j) == 0.0) ac.coeffRef(j, j) = 1.0;
    }
    galerkin_ms = ms_since(t0);
    if (!factor.analyzed()) factor.analyze(ac);
    const auto t1 = Clock::now();
    ok = factor.factorize(ac);
    factor_ms = ms_since(t1);
  }
};

// The symmetric two-level cycle: forward Gauss-Seidel, coarse correction, backward Gauss-Seidel.
struct TwoLevel {
  const Matrix& full_h;  // the current H, both triangles
  const CoarseLevel& coarse;
  int sweeps = 1;        // Gauss-Seidel sweeps before and after the coarse correction
  VecX operator()(const VecX& r) const {
    VecX x = VecX::Zero(r.size());
    VecX residual = r;
    for (int i = 0; i < sweeps; ++i) {
      VecX step = residual;
      full_h.triangularView<Eigen::Lower>().solveInPlace(step);
      x += step;
      residual = r - full_h * x;
    }
    const VecX restricted = coarse.p.transpose() * residual;
    const VecX correction = coarse.factor.solve(restricted);
    x += coarse.p * correction;
    for (int i = 0; i < sweeps; ++i) {
      VecX step = r - full_h * x;
      full_h.triangularView<Eigen::Upper>().solveInPlace(step);
      x += step;
    }
    return x;
  }
};

// CG iterations on full_h to each relative residual in `tolerances`, from zero; 500 means it did not get there.
template <typename Preconditioner>
std::vector<int> cg_iterations(const Matrix& full_h, const Preconditioner& precondition, const VecX& rhs,
                               const std::vector<double>& tolerances) {
  std::vector<int> reached(tolerances.size(), 500);
  VecX x = VecX::Zero(rhs.size()), r = rhs, z = precondition(r), p = z;
  double rz = r.dot(z);
  for (int it = 0; it < 500; ++it) {
    bool all = true;
    for (std::size_t k = 0; k < tolerances.size(); ++k) {
      if (reached[k] == 500 && r.norm() <= tolerances[k] * rhs.norm()) reached[k] = it;
      all = all && reached[k] < 500;
    }
    if (all) break;
    const VecX hp = full_h * p;
    const double alpha = rz / p.dot(hp);
    x += alpha * p;
    r -= alpha * hp;
    z = precondition(r);
    const double next = r.dot(z);
    p = z + (next / rz) * p;
    rz = next;
  }
  return reached;
}

Matrix both_triangles(const Matrix& upper) {
  Matrix full = upper.selfadjointView<Eigen::Upper>();
  return full;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Two-level preconditioning of the moving sheet's Hessian"};
  int triangles = 6000, step = 30, sweeps = 1;
  std::vector<int> coarsening = {4, 16};
  app.add_option("--triangles", triangles, "target triangle count");
  app.add_option("--step", step, "step whose Hessian is solved")->check(CLI::Range(2, 1000));
  app.add_option("--coarsening", coarsening, "coarse meshes: this many times fewer triangles")->delimiter(',');
  app.add_option("--sweeps", sweeps, "Gauss-Seidel sweeps before and after the coarse correction")
      ->check(CLI::Range(1, 20));
  CLI11_PARSE(app, argc, argv);

  const bench::BenchmarkSheet sheet(triangles);
  const ShellModel& model = sheet.model;
  const std::vector<int> lags = {0, 1, 2, 5, 10};
  const double dt_s = 0.01;
  bench::CirclingStates states;
  try {
    states = bench::circling_states(sheet, step + lags.back(), dt_s);
  } catch (const std::runtime_error& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  const std::vector<VecX>& xs = states.x;
  const std::vector<VecX>& vs = states.v;
  const DofMap dofs = model.hold_clamps(sheet.clamps, sheet.poses);
  const Material& material = model.material();
  // Step k's Hessian at its start, as the linearised step assembles it.
  auto step_hessian = [&](int k) {
    InertiaTerm inertia(model.vertex_masses_kg(), material.mass_damping_1_s);
    inertia.set_step(xs[k - 1], vs[k - 1], dt_s);
    ViscosityTerm viscosity(model.membrane().elements(), model.vertex_count(), material.tensile_viscosity_Ns_m,
                            material.shear_viscosity_Ns_m);
    viscosity.set_step(xs[k - 1], dt_s);
    std::vector<const EnergyTerm*> terms = model.potential_terms();
    terms.push_back(&inertia);
    terms.push_back(&viscosity);
    return hessian_at(dofs, Objective(terms), xs[k]);
  };
  const Matrix h0 = step_hessian(step);
  const Matrix full0 = both_triangles(h0);
  const VecX rhs = VecX::Random(h0.cols());
  const std::vector<double> tolerances = {1e-2, 1e-6};

  SparseCholesky direct;
  direct.analyze(h0);
  auto t = Clock::now();
  direct.factorize(h0);
  const double direct_ms = ms_since(t);
  t = Clock::now();
  for (int i = 0; i < 10; ++i) (void)direct.solve(rhs);
  const double direct_solve_ms = ms_since(t) / 10;
  fmt::print("multilevel study: {} triangles, {} free DOFs, step {}'s Hessian, random right-hand side\n",
             model.mesh().triangle_count(), dofs.free_dof_count(), step);
  fmt::print("  direct: factorisation {:.2f} ms ({:.1f} MFlop), one solve {:.2f} ms\n", direct_ms,
             1e-6 * direct.factor_flops(), direct_solve_ms);
  t = Clock::now();
  VecX sink = VecX::Zero(rhs.size());
  for (int i = 0; i < 10; ++i) sink += full0 * rhs;
  const double matvec_ms = ms_since(t) / 10;
  t = Clock::now();
  for (int i = 0; i < 10; ++i) {
    VecX step = rhs;
    full0.triangularView<Eigen::Lower>().solveInPlace(step);
    sink += step;
  }
  const double sweep_ms = ms_since(t) / 10;
  if (!sink.allFinite()) return 1;
  fmt::print("  fine level: product with H {:.2f} ms, one Gauss-Seidel sweep {:.2f} ms\n", matvec_ms, sweep_ms);
  {
    const auto jacobi_free = [](const VecX& r) { return r; };
    const std::vector<int> plain = cg_iterations(full0, jacobi_free, rhs, tolerances);
    fmt::print("  CG without a preconditioner: {} / {} iterations to 1e-2 / 1e-6\n", plain[0], plain[1]);
  }

  for (int factor_of : coarsening) {
    const SheetMesh coarse_mesh = make_rectangular_sheet(
        bench::kWidth_m, bench::kHeight_m,
        edge_length_for_triangle_count(bench::kWidth_m, bench::kHeight_m, triangles / factor_of));
    CoarseLevel coarse;
    coarse.p = prolongation(coarse_mesh, model.mesh(), dofs);
    coarse.build(full0);
    if (!coarse.ok) {
      fmt::print("  coarse {} triangles: Galerkin operator not positive definite\n", coarse_mesh.triangle_count());
      continue;
    }
    t = Clock::now();
    const TwoLevel cycle0{full0, coarse, sweeps};
    for (int i = 0; i < 10; ++i) sink += cycle0(rhs);
    const double cycle_ms = ms_since(t) / 10;
    fmt::print("  coarse {} triangles ({} DOFs): Galerkin product {:.2f} ms, factorisation {:.2f} ms ({:.1f} MFlop), "
               "one cycle {:.2f} ms\n",
               coarse_mesh.triangle_count(), 3 * coarse_mesh.vertex_count(), coarse.galerkin_ms, coarse.factor_ms,
               1e-6 * coarse.factor.factor_flops(), cycle_ms);
    for (int lag : lags) {
      // The coarse factor of step `step`, the sweeps and products on step + lag's Hessian.
      const Matrix full = lag == 0 ? full0 : both_triangles(step_hessian(step + lag));
      const TwoLevel cycle{full, coarse, sweeps};
      const std::vector<int> n = cg_iterations(full, cycle, rhs, tolerances);
      CoarseLevel fresh;
      fresh.p = coarse.p;
      fresh.build(full);
      const std::vector<int> m = cg_iterations(full, TwoLevel{full, fresh, sweeps}, rhs, tolerances);
      fmt::print("    lag {:2d}: CG {:3d} / {:3d} iterations to 1e-2 / 1e-6 with the old coarse factor, "
                 "{:3d} / {:3d} with a fresh one\n",
                 lag, n[0], n[1], m[0], m[1]);
    }
  }
  return 0;
}
