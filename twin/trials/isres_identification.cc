// The paper's identification (section 4.3.2-4.3.3): screening of 27 candidates, bounds around
// the best, NLopt GN_ISRES on Eq. 11.
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlopt.hpp>

#include "twin/trials/identification.h"

namespace twin {
namespace {

bool is_paper_parameter_set(const std::vector<MaterialParameter>& p) {
  return p == std::vector<MaterialParameter>{MaterialParameter::kTensile, MaterialParameter::kShear,
                                             MaterialParameter::kBending};
}

// Eq. 11 for a failed simulation: worse than any sheet that hangs (metres of error).
constexpr double kFailedObjective_m = 1e3;

}  // namespace

std::vector<VecX> paper_screening_candidates(const IdentificationProblem& problem) {
  if (!is_paper_parameter_set(problem.parameters())) {
    throw std::invalid_argument("the paper's screening varies exactly tensile_N_m, shear_N_m and bending_Nm");
  }
  std::vector<VecX> candidates;
  for (double tensile : {500.0, 5000.0, 50000.0}) {
    for (double shear : {500.0, 5000.0, 50000.0}) {
      for (double bending : {0.01, 0.001, 0.0001}) {
        candidates.push_back(Eigen::Vector3d(std::log(tensile), std::log(shear), std::log(bending)));
      }
    }
  }
  return candidates;
}

Material paper_middle_candidate(const Trial& trial) {
  Material m;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 5000.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 1e-3;
  m.poisson_ratio = 0.3;
  m.thickness_m = trial.thickness_m;
  m.name = trial.material_name;
  return m;
}

IdentificationResult identify_isres(IdentificationProblem& problem, const IsresOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int simulations_before = problem.simulations();
  IdentificationResult result;
  result.method = "paper: screening + GN_ISRES";
  // Equilibria continued from another method's materials would carry its choice of branches.
  problem.forget_warm_starts();
  result.objective_name = fmt::format("Eq. 11, sum of Algorithm 1 mean + {:g} max (m)", options.max_weight);

  // 1. Screening: every candidate from the flat sheet; failures removed; the best starts.
  double best = std::numeric_limits<double>::infinity();
  VecX best_x;
  for (const VecX& candidate : paper_screening_candidates(problem)) {
    const auto e = problem.evaluate(candidate, Derivatives::kNone, options.max_weight);
    ++result.evaluations;
    if (e.usable() && e.nearest_score_m < best) {
      best = e.nearest_score_m;
      best_x = candidate;
    }
  }
  if (best_x.size() == 0) {
    result.stop_reason = "every screening candidate failed to simulate";
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.simulations = problem.simulations() - simulations_before;
    return result;
  }

  result.start_coordinates = best_x;
  // 2. Bounds around the best, as multiples of it.
  const int P = static_cast<int>(best_x.size());
  std::vector<double> lower(P), upper(P), x(P);
  for (int j = 0; j < P; ++j) {
    const bool bending = problem.parameters()[j] == MaterialParameter::kBending;
    lower[j] = best_x(j) + std::log(bending ? options.bending_lower : options.stiffness_lower);
    upper[j] = best_x(j) + std::log(bending ? options.bending_upper : options.stiffness_upper);
    x[j] = best_x(j);
  }

  // 3. ISRES, seeded, on Eq. 11.
  nlopt::srand(options.seed);
  nlopt::opt opt(nlopt::GN_ISRES, static_cast<unsigned>(P));
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_maxeval(options.max_evaluations);
  struct Context {
    IdentificationProblem* problem;
    const IsresOptions* options;
    IdentificationResult* result;
  } context{&problem, &options, &result};
  opt.set_min_objective(
      [](unsigned n, const double* v, double*, void* data) {
        auto* c = static_cast<Context*>(data);
        const auto e = c->problem->evaluate(Eigen::Map<const VecX>(v, n), Derivatives::kNone, c->options->max_weight);
        ++c->result->evaluations;
        return e.usable() ? e.nearest_score_m : kFailedObjective_m;
      },
      &context);
  double value = best;
  try {
    const nlopt::result r = opt.optimize(x, value);
    result.stop_reason = r == nlopt::MAXEVAL_REACHED ? "evaluation budget reached" : fmt::format("NLopt result {}", static_cast<int>(r));
  } catch (const std::exception& e) {
    result.stop_reason = fmt::format("NLopt stopped: {}", e.what());
  }
  result.coordinates = Eigen::Map<const VecX>(x.data(), P);
  result.objective = value;
  result.material = problem.material_at(result.coordinates);
  result.simulations = problem.simulations() - simulations_before;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace twin
