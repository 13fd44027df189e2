// Why a lagged factorisation is a poor preconditioner for the moving sheet, measured (issue 2).
//
// The implicit step's linear system changes from step to step; the solver reuses an older
// Cholesky factor as a CG preconditioner until CG gets too slow (newton_linear_solver.h). On the
// benchmark sheet (benchmark_sheet.h) this program steps the circling clamp with linearized
// backward Euler, factorises the step's Hessian at one step and counts the CG iterations that
// factor needs on the Hessian some steps later, with every part new and with only one part new:
// the membrane's material stiffness (A J^T C J, which turns with the elements), its geometric
// stiffness (the stress term), the hinge bending, and the viscosity (whose Jacobian is taken at
// the step's start). The last column applies the old factor in rotated frames (z = R L^-T L^-1
// R^T r, R a rotation per vertex from its normal and an edge at both times), which would undo
// rigid turning of the material stiffness: it barely helps (measured at 6k: 5/10/15/29/82 CG
// iterations at lags 1/2/3/5/10 unwarped, 5/9/11/20/39 warped), so the ageing is the elements
// turning against their neighbours (the sheet bending), not the sheet turning. It then prices
// the cheaper factor of a 1-ring pattern (the hinges' two wing-tip vertices are not 1-ring
// neighbours; their couplings are lumped onto the diagonal, so the matrix stays positive
// definite) against the full pattern's.
//
// Usage: twin_preconditioner_study [--triangles 6000] [--start-step 30]

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "twin/bench/benchmark_sheet.h"
#include "twin/model/energy_term.h"
#include "twin/model/hessian_pattern.h"
#include "twin/model/inertia_term.h"
#include "twin/model/membrane_energy.h"
#include "twin/model/objective.h"
#include "twin/solvers/sparse_cholesky.h"
#include "twin/model/viscosity_term.h"

namespace {

using namespace twin;
using Matrix = HessianPattern::Matrix;
using Clock = std::chrono::steady_clock;

// The membrane's Hessian with its material part (A J^T C J) at positions `material_at` and its
// geometric (stress) part at `stress_at`, projected as the solver projects it.
class SplitMembrane final : public ElementTerm<3> {
 public:
  SplitMembrane(const std::vector<MembraneElement>& elements, int vertex_count, const Mat3& stiffness_N_m,
                const VecX& material_at, const VecX& stress_at)
      : elements_(elements), stiffness_(stiffness_N_m), material_at_(material_at), stress_at_(stress_at) {
    std::vector<int> vertices;
    for (const MembraneElement& e : elements) vertices.insert(vertices.end(), e.v.begin(), e.v.end());
    set_elements(std::move(vertices), vertex_count);
  }
  std::string_view name() const override { return "split membrane"; }

 protected:
  double element_energy(int e, const ElementVector&, ElementVector*, ElementMatrix* h,
                        HessianMode mode) const override {
    if (!h) return 0.0;
    const MembraneElement& el = elements_[e];
    Vec9 material_x, stress_x;
    for (int k = 0; k < 3; ++k) {
      material_x.segment<3>(3 * k) = material_at_.segment<3>(3 * el.v[k]);
      stress_x.segment<3>(3 * k) = stress_at_.segment<3>(3 * el.v[k]);
    }
    Mat9 at_stress;
    membrane_energy(el, stiffness_, stress_x, nullptr, &at_stress, mode);
    *h = at_stress - material_part(el, stress_x) + material_part(el, material_x);
    return 0.0;
  }

 private:
  Mat9 material_part(const MembraneElement& el, const Vec9& xe) const {
    StrainJacobian j;
    membrane_strain(el, xe, &j);
    return el.rest_area_m2 * j.transpose() * stiffness_ * j;
  }

  const std::vector<MembraneElement>& elements_;
  Mat3 stiffness_;
  const VecX& material_at_;
  const VecX& stress_at_;
};

// Sum of the projected Hessians of (term, positions) pairs over the free vertices.
Matrix hessian_of(const DofMap& dofs, const std::vector<std::pair<const EnergyTerm*, const VecX*>>& parts) {
  Matrix sum;
  for (const auto& [term, x] : parts) {
    const Objective objective({term});
    HessianPattern pattern(dofs, objective.stencils());
    objective.evaluate(*x, nullptr, &pattern, HessianMode::kProjected);
    sum = sum.size() == 0 ? pattern.matrix() : Matrix(sum + pattern.matrix());
  }
  return sum;
}

// CG iterations to a relative residual of 1e-2 on `upper` (symmetric, upper triangle stored),
// preconditioned by `precondition` (r -> z), from zero; 200 means it did not get there.
template <typename Preconditioner>
int cg_iterations(const Matrix& upper, const Preconditioner& precondition, const VecX& rhs) {
  const auto h = upper.selfadjointView<Eigen::Upper>();
  VecX x = VecX::Zero(rhs.size()), r = rhs, z = precondition(r), p = z;
  double rz = r.dot(z);
  for (int it = 0; it < 200; ++it) {
    if (r.norm() <= 1e-2 * rhs.norm()) return it;
    const VecX hp = h * p;
    const double alpha = rz / p.dot(hp);
    x += alpha * p;
    r -= alpha * hp;
    z = precondition(r);
    const double next = r.dot(z);
    p = z + (next / rz) * p;
    rz = next;
  }
  return 200;
}

int cg_iterations(const Matrix& upper, const SparseCholesky& factor, const VecX& rhs) {
  return cg_iterations(upper, [&](const VecX& r) { return factor.solve(r); }, rhs);
}

// `full` restricted to the pattern of `pattern_of`, with each dropped |h_ij| added to both
// diagonal entries (a diagonally dominant correction keeps it positive definite).
Matrix restricted_lumped(const Matrix& full, const Matrix& pattern_of) {
  Matrix out = pattern_of;
  out.coeffs().setZero();
  VecX lumped = VecX::Zero(out.cols());
  for (int j = 0; j < full.outerSize(); ++j) {
    for (Matrix::InnerIterator it(full, j); it; ++it) {
      bool kept = false;
      for (Matrix::InnerIterator slot(out, j); slot; ++slot) {
        if (slot.row() == it.row()) {
          slot.valueRef() += it.value();
          kept = true;
          break;
        }
      }
      if (!kept) {
        lumped[it.row()] += std::abs(it.value());
        lumped[j] += std::abs(it.value());
      }
    }
  }
  for (int j = 0; j < out.outerSize(); ++j) out.coeffRef(j, j) += lumped[j];
  return out;
}

// Per-vertex rotations from x_from to x_to: each vertex's frame (its area-weighted normal and
// the direction to its first neighbour, made orthogonal) at both, R = Q_to Q_from^T.
std::vector<Mat3> vertex_rotations(const SheetMesh& mesh, const VecX& x_from, const VecX& x_to) {
  const int n = mesh.vertex_count();
  std::vector<Vec3> n_from(n, Vec3::Zero()), n_to(n, Vec3::Zero());
  std::vector<int> neighbour(n, -1);
  for (const auto& t : mesh.triangles) {
    auto p = [&](const VecX& x, int k) { return Vec3(x.segment<3>(3 * t[k])); };
    const Vec3 a = (p(x_from, 1) - p(x_from, 0)).cross(p(x_from, 2) - p(x_from, 0));
    const Vec3 b = (p(x_to, 1) - p(x_to, 0)).cross(p(x_to, 2) - p(x_to, 0));
    for (int k = 0; k < 3; ++k) {
      n_from[t[k]] += a;
      n_to[t[k]] += b;
      if (neighbour[t[k]] < 0) neighbour[t[k]] = t[(k + 1) % 3];
    }
  }
  auto frame = [&](const VecX& x, const Vec3& normal, int i) {
    const Vec3 nz = normal.normalized();
    const Vec3 e = x.segment<3>(3 * neighbour[i]) - x.segment<3>(3 * i);
    const Vec3 tx = (e - e.dot(nz) * nz).normalized();
    Mat3 q;
    q << tx, nz.cross(tx), nz;
    return q;
  };
  std::vector<Mat3> r(n);
  for (int i = 0; i < n; ++i) r[i] = frame(x_to, n_to[i], i) * frame(x_from, n_from[i], i).transpose();
  return r;
}

// As cg_iterations, with the factor applied in the rotated frames: z = R L^-T L^-1 R^T r.
int warped_cg_iterations(const Matrix& upper, const SparseCholesky& factor, const VecX& rhs, const DofMap& dofs,
                         const std::vector<Mat3>& rotation) {
  auto rotate = [&](const VecX& in, bool transpose) {
    VecX out(in.size());
    for (int v = 0; v < dofs.vertex_count(); ++v) {
      const int f = dofs.free_index(v);
      if (f < 0) continue;
      out.segment<3>(3 * f) = transpose ? Vec3(rotation[v].transpose() * in.segment<3>(3 * f))
                                        : Vec3(rotation[v] * in.segment<3>(3 * f));
    }
    return out;
  };
  return cg_iterations(upper, [&](const VecX& r) { return rotate(factor.solve(rotate(r, true)), false); }, rhs);
}

double factorize_ms(SparseCholesky& factor, const Matrix& upper) {
  constexpr int kRepeats = 5;
  const auto start = Clock::now();
  for (int i = 0; i < kRepeats; ++i) factor.factorize(upper);
  return 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / kRepeats;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Which part of the moving sheet's Hessian ages a lagged preconditioner"};
  int triangles = 6000, start_step = 30;
  app.add_option("--triangles", triangles, "target triangle count");
  app.add_option("--start-step", start_step, "step whose Hessian is factorised")->check(CLI::Range(2, 1000));
  CLI11_PARSE(app, argc, argv);

  const bench::BenchmarkSheet sheet(triangles);
  const ShellModel& model = sheet.model;
  // States x_k at the start of each step k (and v_k), stepping with the cell's linearized scheme.
  const std::vector<int> lags = {1, 2, 3, 5, 10, 20, 40};
  const double dt_s = 0.01;
  bench::CirclingStates states;
  try {
    states = bench::circling_states(sheet, start_step + lags.back(), dt_s);
  } catch (const std::runtime_error& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  const std::vector<VecX>& xs = states.x;
  const std::vector<VecX>& vs = states.v;
  const DofMap dofs = model.hold_clamps(sheet.clamps, sheet.poses);
  const std::vector<const EnergyTerm*> potential = model.potential_terms();
  const EnergyTerm* membrane = potential[0];
  const EnergyTerm* bending = potential[1];
  const Material& material = model.material();

  // The Hessian of step k's objective at the step's first Newton iterate (its start).
  InertiaTerm inertia(model.vertex_masses_kg(), material.mass_damping_1_s);
  inertia.set_step(xs[start_step - 1], vs[start_step - 1], dt_s);
  auto viscosity_at = [&](int k) {
    auto term = std::make_unique<ViscosityTerm>(model.membrane().elements(), model.vertex_count(),
                                                material.tensile_viscosity_Ns_m, material.shear_viscosity_Ns_m);
    term->set_step(xs[k - 1], dt_s);
    return term;
  };
  const VecX& x0 = xs[start_step];
  const auto viscosity0 = viscosity_at(start_step);
  const Matrix h0 = hessian_of(dofs, {{membrane, &x0}, {bending, &x0}, {&inertia, &x0}, {viscosity0.get(), &x0}});
  SparseCholesky factor;
  factor.analyze(h0);
  const double full_ms = factorize_ms(factor, h0);
  const VecX rhs = VecX::Random(h0.cols());

  fmt::print("preconditioner study: {} triangles, {} free DOFs, factor of step {}'s Hessian; CG iterations "
             "to a relative residual of 1e-2 on the Hessian of a later step (a random right-hand side)\n",
             model.mesh().triangle_count(), dofs.free_dof_count(), start_step);
  fmt::print("{:>5} {:>10} {:>9} {:>9} {:>10} {:>10} {:>8} {:>10} {:>8}\n", "lag", "max move", "all new",
             "membrane", " material", "geometric", "bending", "viscosity", "warped");
  const Mat3 stiffness = material.membrane_stiffness();
  for (int lag : lags) {
    const VecX& x1 = xs[start_step + lag];
    const auto viscosity1 = viscosity_at(start_step + lag);
    const SplitMembrane new_material(model.membrane().elements(), model.vertex_count(), stiffness, x1, x0);
    const SplitMembrane new_stress(model.membrane().elements(), model.vertex_count(), stiffness, x0, x1);
    auto count = [&](const std::vector<std::pair<const EnergyTerm*, const VecX*>>& parts) {
      return cg_iterations(hessian_of(dofs, parts), factor, rhs);
    };
    const auto rotation = vertex_rotations(model.mesh(), x0, x1);
    fmt::print("{:>5} {:>7.2f} mm {:>9} {:>9} {:>10} {:>10} {:>8} {:>10} {:>8}\n", lag,
               1e3 * (x1 - x0).cwiseAbs().maxCoeff(),
               count({{membrane, &x1}, {bending, &x1}, {&inertia, &x1}, {viscosity1.get(), &x1}}),
               count({{membrane, &x1}, {bending, &x0}, {&inertia, &x0}, {viscosity0.get(), &x0}}),
               count({{&new_material, &x0}, {bending, &x0}, {&inertia, &x0}, {viscosity0.get(), &x0}}),
               count({{&new_stress, &x0}, {bending, &x0}, {&inertia, &x0}, {viscosity0.get(), &x0}}),
               count({{membrane, &x0}, {bending, &x1}, {&inertia, &x0}, {viscosity0.get(), &x0}}),
               count({{membrane, &x0}, {bending, &x0}, {&inertia, &x0}, {viscosity1.get(), &x1}}),
               warped_cg_iterations(hessian_of(dofs, {{membrane, &x1}, {bending, &x1}, {&inertia, &x1},
                                                      {viscosity1.get(), &x1}}),
                                    factor, rhs, dofs, rotation));
  }

  // A factor of the current Hessian on the 1-ring pattern, against the full pattern's.
  const Matrix one_ring = restricted_lumped(h0, hessian_of(dofs, {{membrane, &x0}, {&inertia, &x0}}));
  SparseCholesky ring_factor;
  ring_factor.analyze(one_ring);
  const double ring_ms = factorize_ms(ring_factor, one_ring);
  const double solve_ms = [&] {
    const auto start = Clock::now();
    VecX y = rhs;
    for (int i = 0; i < 20; ++i) y = factor.solve(y).normalized();
    return 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / 20;
  }();
  fmt::print("full pattern:   factor nonzeros {:9.0f}  {:6.1f} MFlop  factorisation {:6.2f} ms  one solve {:.2f} ms\n",
             factor.factor_nonzeros(), 1e-6 * factor.factor_flops(), full_ms, solve_ms);
  fmt::print("1-ring pattern: factor nonzeros {:9.0f}  {:6.1f} MFlop  factorisation {:6.2f} ms  CG iterations "
             "on the same step's full Hessian {}\n",
             ring_factor.factor_nonzeros(), 1e-6 * ring_factor.factor_flops(), ring_ms,
             cg_iterations(h0, ring_factor, rhs));
  return 0;
}
