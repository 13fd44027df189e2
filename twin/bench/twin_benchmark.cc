// Benchmark of the sheet twin (issue 2): the paper's composite sheet (1.17 x 0.975 m,
// 0.3 kg/m^2, tensile 5000 N/m, shear 5000 N/m, bending 0.001 N*m) held by four clamps, on
// meshes of about 1.5k, 6k and 24k triangles, with one and two threads. For each it prints
// the static equilibrium from the flat sheet (time, Newton iterations; then again through
// coarser meshes of the same sheet, coarse_to_fine_statics.h, and how far apart the two
// equilibria are), the implicit
// backward-Euler step (dt 10 ms, median and 90th percentile over >= 100 steps after warm-up,
// while one clamp circles so the sheet keeps moving) solved to convergence and linearised (one
// Newton iteration, the paper engine's scheme), and the peak resident memory. Then where a
// linearised step's time goes, on the moving sheet after the timed steps: one evaluation of
// energy and gradient, one assembly of the projected Hessian, one numeric factorisation and one
// solve with it (median of 20 each).
//
// Each (mesh, threads) case runs in its own process so peak RSS and thread settings are its own.
// Usage: twin_benchmark [--steps N] [--sizes 1500,6000,24000] [--threads 1,2] [--linearized-only]
//                      [--static-only]

#include <omp.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "twin/bench/benchmark_sheet.h"
#include "twin/model/hessian_pattern.h"
#include "twin/solvers/implicit_stepper.h"
#include "twin/model/objective.h"
#include "twin/solvers/sparse_cholesky.h"
#include "twin/solvers/coarse_to_fine_statics.h"
#include "twin/solvers/static_solver.h"
#include "twin/model/viscosity_term.h"

namespace {

using namespace twin;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, std::floor(p * v.size())))];
}

constexpr double step_dt_s = 0.01;
constexpr int warm_up_steps = 10;

template <typename F>
double median_ms(int repeats, F&& work) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = Clock::now();
    work();
    ms.push_back(1e3 * seconds_since(t0));
  }
  return percentile(ms, 0.5);
}

// The parts of a linearised step (what ImplicitStepper and NewtonLinearSolver do in it), timed
// one by one on the moving sheet x, v with the clamps where they are at t_s.
void print_step_parts(const bench::BenchmarkSheet& sheet, const VecX& x, const VecX& v, double t_s) {
  const DofMap dofs = sheet.model.hold_clamps(sheet.clamps, sheet.circling_poses(t_s));
  const ShellModel& model = sheet.model;
  InertiaTerm inertia(model.vertex_masses_kg(), model.material().mass_damping_1_s);
  inertia.set_step(x, v, step_dt_s);
  ViscosityTerm viscosity(model.membrane().elements(), model.vertex_count(),
                          model.material().tensile_viscosity_Ns_m, model.material().shear_viscosity_Ns_m);
  viscosity.set_step(x, step_dt_s);
  // The stepper's terms: potential, inertia, and the strain-rate viscosity when there is some.
  std::vector<const EnergyTerm*> terms = model.potential_terms();
  terms.push_back(&inertia);
  if (viscosity.active()) terms.push_back(&viscosity);
  const Objective objective(terms);
  HessianPattern hessian(dofs, objective.stencils());
  SparseCholesky cholesky;
  cholesky.analyze(hessian.matrix());
  VecX grad(x.size());
  const int repeats = 20;
  const double gradient_ms =
      median_ms(repeats, [&] { objective.evaluate(x, &grad, nullptr, HessianMode::kProjected); });
  const double assembly_ms =
      median_ms(repeats, [&] { objective.evaluate(x, nullptr, &hessian, HessianMode::kProjected); });
  bool factorized = true;
  const double factor_ms = median_ms(repeats, [&] { factorized = cholesky.factorize(hessian.matrix()) && factorized; });
  const VecX rhs = VecX::Ones(hessian.matrix().rows());
  VecX solution;
  const double solve_ms = median_ms(repeats, [&] { solution = cholesky.solve(rhs); });
  fmt::print("    step parts     energy+gradient {:.2f} ms  Hessian assembly {:.2f} ms  factorisation {:.2f} ms "
             "({:.1f} MFlop, {:.0f} factor non-zeros{})  one solve {:.2f} ms\n",
             gradient_ms, assembly_ms, factor_ms, cholesky.factor_flops() / 1e6, cholesky.factor_nonzeros(),
             factorized ? "" : ", NOT positive definite", solve_ms);
}

double cg_vertex_error_m = -1.0;  // < 0: the stepper's own
double cycle_ms = 100.0 / 3.0;     // the cell's 30 Hz
bool static_only = false;          // the static equilibria only, no steps

// The static equilibrium from flat again, through meshes of 1/16 and 1/4 of the triangles
// (coarse_to_fine_statics.h), against the direct solve's (`direct`, `x_direct`). Returns whether
// it converged.
bool print_static_through_coarser_meshes(const bench::BenchmarkSheet& sheet, int triangles,
                                         const SolveReport& direct, const VecX& x_direct) {
  const ShellModel& model = sheet.model;
  std::vector<SheetMesh> coarse;
  for (int divisor : {16, 4}) {
    if (triangles / divisor < 100) continue;
    coarse.push_back(make_rectangular_sheet(
        bench::kWidth_m, bench::kHeight_m,
        edge_length_for_triangle_count(bench::kWidth_m, bench::kHeight_m, triangles / divisor)));
  }
  const auto build_start = Clock::now();
  CoarseToFineStatics multilevel(model, sheet.clamps, std::move(coarse));
  const double build_ms = 1e3 * seconds_since(build_start);
  VecX xm = sheet.flat;
  const CoarseToFineReport r = multilevel.solve(sheet.poses, xm);
  std::string levels;
  for (std::size_t i = 0; i < r.levels.size(); ++i) {
    levels += fmt::format("{}{} tris {} it {:.0f} ms", i ? ", " : "", r.level_triangles[i],
                          r.levels[i].iterations, 1e3 * r.levels[i].seconds);
  }
  fmt::print("    static from flat through coarser meshes {:8.1f} ms ({}; {} fallbacks; building the levels "
             "{:.0f} ms, once) {}\n",
             1e3 * r.total.seconds, levels, r.total.fallbacks, build_ms,
             r.total.usable() ? "converged" : to_string(r.total.status));
  if (r.total.usable() && direct.usable()) {
    double largest_m = 0.0;
    for (int v = 0; v < model.vertex_count(); ++v) {
      largest_m = std::max(largest_m, (xm.segment<3>(3 * v) - x_direct.segment<3>(3 * v)).norm());
    }
    fmt::print("      vs the direct solve: largest vertex distance {:.4f} mm, energy {:.9g} J vs {:.9g} J "
               "(relative difference {:.2e})\n",
               1e3 * largest_m, r.total.energy_J, direct.energy_J,
               std::abs(r.total.energy_J - direct.energy_J) / std::abs(direct.energy_J));
  }
  std::fflush(stdout);
  return r.total.usable();
}

int run_case(int triangles, int threads, int steps, bool converged_too) {
  omp_set_num_threads(threads);
  const bench::BenchmarkSheet sheet(triangles);
  const ShellModel& model = sheet.model;
  const ClampSet& clamps = sheet.clamps;
  const std::vector<ClampPose>& poses = sheet.poses;

  VecX x = sheet.flat;
  StaticSolver statics(model);
  const auto static_start = Clock::now();
  const SolveReport equilibrium = statics.solve(clamps, poses, x);
  const double static_ms = 1e3 * seconds_since(static_start);
  fmt::print("triangles {:6d}  vertices {:6d}  threads {}  | static {:8.1f} ms  {:4d} Newton iterations  {}\n",
             model.mesh().triangle_count(), model.vertex_count(), threads, static_ms, equilibrium.iterations,
             equilibrium.usable() ? "converged" : to_string(equilibrium.status));
  const bool multilevel_solved = print_static_through_coarser_meshes(sheet, triangles, equilibrium, x);
  if (static_only) return equilibrium.usable() && multilevel_solved ? 0 : 1;

  // Time the implicit schemes from the same equilibrium, each with its own stepper. With
  // `cycle_ms` > 0 each step starts on a cycle of that period, as the cell's twin steps (the
  // time between is the background factorisation's). With `shadow`, every step is also taken
  // from the same state by a stepper with those options (untimed), and the largest vertex
  // distance between the two steps' results is kept.
  struct StepFigures {
    std::vector<double> ms;
    int newton = 0, failed = 0, substeps = 0, factorizations = 0, cg = 0, fallbacks = 0;
    double largest_deviation_m = 0.0, wait_s = 0.0;
    int background = 0;  // predicted Hessians factorised on the worker, warm-up included
    VecX x_end, v_end;  // the sheet after the last step
  };
  auto run_steps = [&](const StepOptions& options, double cycle_ms, const StepOptions* shadow) {
    StepFigures f;
    ImplicitStepper stepper(model), reference(model);
    VecX xs = x, v = VecX::Zero(x.size());
    const double dt = step_dt_s;
    const int warm_up = warm_up_steps;
    auto next_cycle = Clock::now();
    for (int s = 0; s < warm_up + steps; ++s) {
      const std::vector<ClampPose> moving = sheet.circling_poses((s + 1) * dt);
      if (cycle_ms > 0.0) {
        std::this_thread::sleep_until(next_cycle);
        next_cycle += std::chrono::microseconds(static_cast<long>(1e3 * cycle_ms));
      }
      VecX x_ref = xs, v_ref = v;
      const auto t0 = Clock::now();
      const SolveReport r = stepper.step(xs, v, dt, clamps, moving, options);
      const double ms = 1e3 * seconds_since(t0);
      if (shadow) {
        reference.step(x_ref, v_ref, dt, clamps, moving, *shadow);
        for (int i = 0; i < model.vertex_count(); ++i) {
          f.largest_deviation_m = std::max(f.largest_deviation_m, (xs.segment<3>(3 * i) - x_ref.segment<3>(3 * i)).norm());
        }
      }
      if (s < warm_up) continue;
      f.ms.push_back(ms);
      f.newton += r.iterations;
      f.factorizations += r.factorizations;
      f.cg += r.cg_iterations;
      f.fallbacks += r.fallbacks;
      f.wait_s += r.factor_wait_s;
      f.substeps += stepper.last_substeps();
      if (!r.usable()) ++f.failed;
    }
    f.x_end = xs;
    f.v_end = v;
    f.background = stepper.background_factorizations();
    return f;
  };
  const StepFigures converged = converged_too ? run_steps(default_step_options(), 0.0, nullptr) : StepFigures{};
  // The linearised step without background factorisation: factorising on the step's thread.
  const StepOptions factorising = linearized_step_options();
  const StepFigures each_step = run_steps(factorising, 0.0, nullptr);
  StepOptions background = background_linearized_step_options();
  if (cg_vertex_error_m >= 0.0) background.newton.linear.cg_vertex_error_m = cg_vertex_error_m;

  const StepFigures back_to_back = run_steps(background, 0.0, nullptr);
  const StepFigures paced = run_steps(background, cycle_ms, nullptr);
  // Untimed: each step also solved exactly (a factorisation of its own Hessian) from the same state.
  StepOptions exact = factorising;
  exact.newton.linear.reuse_factorization = false;
  const StepFigures compared = run_steps(background, 0.0, &exact);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  fmt::print("    peak RSS {:6.1f} MB\n", usage.ru_maxrss / 1024.0);
  auto print_steps = [&](const char* name, const StepFigures& f) {
    fmt::print("    {}\n      step median {:8.2f} ms  p90 {:8.2f} ms  Newton/step {:5.2f}  "
               "sub-steps/step {:4.2f}  failed {}\n      factorisations waited for/step {:4.2f}  "
               "predicted ones on the worker/step {:4.2f}  waiting for the worker {:.2f} ms/step  CG iterations/step {:5.2f}  "
               "fallbacks {}\n",
               name, percentile(f.ms, 0.5), percentile(f.ms, 0.9),
               static_cast<double>(f.newton) / steps, static_cast<double>(f.substeps) / steps, f.failed,
               static_cast<double>(f.factorizations) / steps,
               static_cast<double>(f.background) / (steps + warm_up_steps), 1e3 * f.wait_s / steps,
               static_cast<double>(f.cg) / steps, f.fallbacks);
  };
  if (converged_too) print_steps("converged BE", converged);
  print_steps("linearized BE, factorising on its own thread", each_step);
  print_steps("linearized BE, background factor, back to back", back_to_back);
  fmt::print("      largest vertex distance from the exactly solved step's result, same states: {:.4f} mm\n",
             1e3 * compared.largest_deviation_m);
  const std::string paced_name = fmt::format("linearized BE, background factor, a step every {:g} ms", cycle_ms);
  print_steps(paced_name.c_str(), paced);
  print_step_parts(sheet, back_to_back.x_end, back_to_back.v_end, (warm_up_steps + steps + 1) * step_dt_s);
  std::fflush(stdout);
  const int failed = converged.failed + each_step.failed + back_to_back.failed + paced.failed + compared.failed;
  return equilibrium.usable() && failed == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Twin benchmark: implicit step and static equilibrium on the paper's sheet"};
  std::vector<int> sizes = {1500, 6000, 24000}, thread_counts = {1, 2};
  int steps = 100, only_size = 0, only_threads = 0;
  bool linearized_only = false;
  app.add_option("--sizes", sizes, "target triangle counts")->delimiter(',');
  app.add_option("--threads", thread_counts, "thread counts")->delimiter(',');
  app.add_option("--steps", steps, "timed implicit steps per case (after 10 warm-up steps)");
  app.add_flag("--linearized-only", linearized_only, "skip the converged backward-Euler steps");
  app.add_option("--cg-vertex-error-m", cg_vertex_error_m,
                 "linearized steps: CG's error bound per vertex (m; default the stepper's)");
  app.add_option("--cycle-ms", cycle_ms, "paced linearized steps: one step per this period (ms)");
  app.add_flag("--static-only", static_only, "only the static equilibria from flat (direct and through coarser meshes)");
  app.add_option("--case-size", only_size)->group("");  // internal: run one case in this process
  app.add_option("--case-threads", only_threads)->group("");
  CLI11_PARSE(app, argc, argv);
  if (only_size > 0) return run_case(only_size, only_threads, steps, !linearized_only);

  fmt::print("twin benchmark: sheet {} x {} m, 0.3 kg/m^2, Y 5000 N/m, G 5000 N/m, D 0.001 N*m, "
             "four clamps, dt 10 ms, {} timed steps; one process per case\n",
             bench::kWidth_m, bench::kHeight_m, steps);
  std::fflush(stdout);
  int status = 0;
  for (int size : sizes) {
    for (int threads : thread_counts) {
      const pid_t pid = fork();
      if (pid == 0) {
        const std::string size_arg = std::to_string(size), threads_arg = std::to_string(threads),
                          steps_arg = std::to_string(steps);
        std::vector<const char*> args = {argv[0], "--case-size", size_arg.c_str(), "--case-threads",
                                         threads_arg.c_str(), "--steps", steps_arg.c_str()};
        if (linearized_only) args.push_back("--linearized-only");
        if (static_only) args.push_back("--static-only");
        const std::string error_arg = fmt::format("{}", cg_vertex_error_m), cycle_arg = fmt::format("{}", cycle_ms);
        args.push_back("--cycle-ms");
        args.push_back(cycle_arg.c_str());
        if (cg_vertex_error_m >= 0.0) {
          args.push_back("--cg-vertex-error-m");
          args.push_back(error_arg.c_str());
        }
        args.push_back(nullptr);
        execv("/proc/self/exe", const_cast<char* const*>(args.data()));
        _exit(127);
      }
      int child = 0;
      waitpid(pid, &child, 0);
      if (!WIFEXITED(child) || WEXITSTATUS(child) != 0) status = 1;
    }
  }
  return status;
}
