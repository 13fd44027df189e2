#include "identify_command.h"

#include <optional>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "twin/trials/discretisation_check.h"
#include "twin/trials/identification.h"
#include "twin/trials/residual_export.h"
#include "twin/trials/clamp_refinement_option.h"

namespace twin_cli {
namespace {

using namespace twin;

std::vector<MaterialParameter> parse_parameter_list(const std::string& list) {
  std::vector<MaterialParameter> result;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (!name.empty()) result.push_back(parse_material_parameter(name));
  }
  if (result.empty()) throw std::invalid_argument("--parameters: expected a comma-separated list of names");
  return result;
}

// Start values and the properties that are not identified: the --start file, or the paper's
// middle candidate (5000 N/m, 5000 N/m, 0.001 N*m) with Poisson 0.3 and the trial's thickness.
Material base_material(const IdentifyArguments& a, const Trial& first) {
  Material m = a.start.empty() ? paper_middle_candidate(first) : read_material_file(a.start);
  m.thickness_m = first.thickness_m;
  m.name = first.material_name + " (identified)";
  if (a.bending_model == "plate") m.bending_model = Material::BendingModel::kPlate;
  if (a.bending_model == "hinge") {
    m.bending_model = Material::BendingModel::kHinge;
    m.bending_coupling_ratio.reset();
    m.twist_ratio.reset();
  }
  return m;
}

struct Row {
  std::string set, trial, stage;
  double nearest_mean_m, nearest_max_m, corr_mean_m, corr_max_m;
};

// Mean over stages of each stage's mean; max over stages (the paper's tables, in cm).
void print_table(const std::string& material, const std::string& method, const std::vector<Row>& rows) {
  fmt::print("\n{:<12} {:<10} {:<6} {:<28} {:>11} {:>9} {:>11} {:>9}\n", "material", "method", "set", "trial",
             "Alg.1 mean", "max (cm)", "corr. mean", "max (cm)");
  for (const Row& r : rows) {
    if (!r.stage.empty()) continue;
    fmt::print("{:<12} {:<10} {:<6} {:<28} {:>11.2f} {:>9.2f} {:>11.2f} {:>9.2f}\n", material, method, r.set, r.trial,
               100 * r.nearest_mean_m, 100 * r.nearest_max_m, 100 * r.corr_mean_m, 100 * r.corr_max_m);
  }
}

std::vector<Row> score_rows(const std::string& set, TrialEvaluator& evaluator, const TrialFit& fit) {
  std::vector<Row> rows;
  Row total{set, std::filesystem::path(evaluator.trial().directory).filename().string(), "", 0, 0, 0, 0};
  int corr_stages = 0;
  for (const StageFit& s : fit.stages) {
    total.nearest_mean_m += s.nearest.mean_m / fit.stages.size();
    total.nearest_max_m = std::max(total.nearest_max_m, s.nearest.max_m);
    if (s.correspondence) {
      total.corr_mean_m += s.correspondence->mean_m;
      total.corr_max_m = std::max(total.corr_max_m, s.correspondence->max_m);
      ++corr_stages;
    }
    rows.push_back({set, total.trial, s.id, s.nearest.mean_m, s.nearest.max_m,
                    s.correspondence ? s.correspondence->mean_m : NAN, s.correspondence ? s.correspondence->max_m : NAN});
  }
  total.corr_mean_m = corr_stages ? total.corr_mean_m / corr_stages : NAN;
  rows.push_back(total);
  return rows;
}

// Which covariance set the interval (identification.h: estimate_uncertainty), and how far the
// twin's discretisation error widened it.
std::string robust_note(const ParameterEstimate& e) {
  if (e.at_search_edge) return "  (the search stopped at the edge of its range: the interval runs to the bound)";
  const std::string kind = e.block_robust ? "stage x quarter blocks: model error" : "Fisher";
  if (e.discretisation_shift == 0.0) return "  (" + kind + ")";
  return fmt::format("  ({}, widened by the discretisation shift {:+.4g})", kind, e.discretisation_shift);
}

void print_estimates(const IdentificationResult& r) {
  fmt::print("\n{}: {} evaluations, {} trial simulations, {:.1f} s, {} ({} = {:.6g})\n", r.method, r.evaluations,
             r.simulations, r.seconds, r.stop_reason, r.objective_name, r.objective);
  for (const ParameterEstimate& e : r.estimates) {
    if (e.determined) {
      fmt::print("  {:<22} {:12.6g}   95 % interval [{:.6g}, {:.6g}]{}\n", parameter_name(e.parameter), e.value, e.lower95,
                 e.upper95, robust_note(e));
    } else if (std::isfinite(e.upper95)) {
      fmt::print("  {:<22} {:12.6g}   NOT DETERMINED by these trials: 95 % interval [{:.6g}, {:.6g}]{}\n",
                 parameter_name(e.parameter), e.value, e.lower95, e.upper95, robust_note(e));
    } else {
      fmt::print("  {:<22} {:12.6g}   NOT DETERMINED: the markers do not respond to it\n", parameter_name(e.parameter),
                 e.value);
    }
  }
  fmt::print("  residual RMS per coordinate {:.3f} mm (scanner noise plus model error)\n", 1e3 * r.noise_sigma_m);
}

}  // namespace

CLI::App* add_identify_command(CLI::App& app, IdentifyArguments& a) {
  CLI::App* cmd = app.add_subcommand("identify", "identify material parameters from scanned trials");
  cmd->add_option("--train", a.train, "training trial directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--test", a.test, "test trial directories (scored, not fitted)")->check(CLI::ExistingDirectory);
  cmd->add_option("--out", a.out, "material file to write (JSON)")->required();
  cmd->add_option("--method", a.method, "gradient (ours), paper (screening + ISRES) or both")
      ->check(CLI::IsMember({"gradient", "paper", "both"}));
  cmd->add_option("--optimizer", a.optimizer,
                  "for --method gradient: lm (Levenberg-Marquardt on the residuals, default) or lbfgs "
                  "(NLopt LD_LBFGS on their mean square)")
      ->check(CLI::IsMember({"lm", "lbfgs"}));
  cmd->add_option("--parameters", a.parameters, "comma-separated parameters to identify");
  cmd->add_option("--start", a.start, "material file with start values and the fixed properties")
      ->check(CLI::ExistingFile);
  cmd->add_option("--bending-model", a.bending_model,
                  "hinge (the paper's, Eq. 10) or plate (a curvature tensor per triangle with the material's "
                  "D12 and D66); default: the start material's, hinge for the paper's")
      ->check(CLI::IsMember({"hinge", "plate"}));
  cmd->add_option("--membrane-model", a.membrane_model,
                  "linear (constant-strain triangles, default) or quadratic (six-node triangles on a mesh of a "
                  "quarter of the triangles refined uniformly once: folds without membrane locking)")
      ->check(CLI::IsMember({"linear", "quadratic"}));
  cmd->add_option("--residuals", a.residuals, "directory for per-marker residual files (CSV, PLY)");
  cmd->add_option("--triangles", a.triangles, "triangles of the twin's sheet mesh")->check(CLI::Range(50, 200000));
  cmd->add_option("--clamp-refinement", a.clamp_refinement,
                  "jaws: halve the twin's edges near each clamp until they are at most 0.4 of its grip radius "
                  "(default); or comma-separated radii (m): each halves the edges within that distance of every "
                  "clamp, in turn; none: no refinement");
  cmd->add_option("--path-triangles", a.path_triangles,
                  "triangles of the coarse mesh a fresh simulation follows the clamps' path on when every "
                  "stage has markers; 0: on the twin itself (default 300)")
      ->check(CLI::Range(0, 200000));
  cmd->add_option("--seed", a.seed, "ISRES random seed");
  cmd->add_option("--max-evaluations", a.max_evaluations, "optimiser evaluation budget (0: default)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--quiet", a.quiet, "no per-evaluation progress lines");
  cmd->add_flag("!--no-discretisation-check", a.discretisation_check,
                "skip simulating the fitted material on a twin of twice the triangles (the report of the "
                "twin's discretisation error beside the residual)");
  return cmd;
}

int run_identify(const IdentifyArguments& a) {
  const std::vector<MaterialParameter> parameters = parse_parameter_list(a.parameters);
  const ClampRefinement refinement = parse_clamp_refinement(a.clamp_refinement);
  const TwinMeshSpec mesh{a.triangles, refinement.radii_m, a.path_triangles, refinement.resolve_jaws,
                          a.membrane_model == "quadratic"};
  std::vector<Trial> train_trials, test_trials;
  for (const std::string& d : a.train) train_trials.push_back(read_trial(d));
  for (const std::string& d : a.test) test_trials.push_back(read_trial(d));
  const Material base = base_material(a, train_trials.front());
  base.validate();
  std::vector<std::unique_ptr<TrialEvaluator>> train, test;
  for (Trial& t : train_trials) train.push_back(std::make_unique<TrialEvaluator>(std::move(t), mesh, base));
  for (Trial& t : test_trials) test.push_back(std::make_unique<TrialEvaluator>(std::move(t), mesh, base));
  std::vector<TrialEvaluator*> training;
  for (auto& t : train) training.push_back(t.get());

  const TrialEvaluator& first = *train.front();
  fmt::print("identify  {} of {} from {} training and {} test trial(s); twin mesh {} triangles, {} vertices{}{}{}\n",
             a.parameters, first.trial().material_name, train.size(), test.size(),
             first.model().mesh().triangle_count(), first.model().vertex_count(),
             mesh.quadratic_membrane
                 ? fmt::format(", quadratic membrane on {} triangles", first.model().mesh().quadratic_patches.size())
                 : std::string(),
             mesh.resolve_jaws ? std::string(" (refined near the clamps until their jaws are resolved)")
             : mesh.clamp_refinement_radii_m.empty()
                 ? std::string()
                 : fmt::format(" (refined near the clamps within {} m)", fmt::join(mesh.clamp_refinement_radii_m, ", ")),
             first.path_mesh_triangles() == first.model().mesh().triangle_count()
                 ? std::string()
                 : fmt::format("; clamp path followed on {} triangles", first.path_mesh_triangles()));
  IdentificationProblem problem(training, base, parameters);
  int count = 0;
  if (!a.quiet) {
    problem.on_evaluation = [&](const VecX& v, const IdentificationProblem::Evaluation& e) {
      std::string values;
      for (Eigen::Index j = 0; j < v.size(); ++j) {
        values += fmt::format(" {}={:.4g}", parameter_name(parameters[j]),
                              from_search_coordinate(parameters[j], v(j)));
      }
      if (e.usable()) {
        fmt::print("  eval {:4d}{}  rms {:.3f} mm  Eq.11 {:.2f} cm  ({:.2f} s)\n", ++count, values,
                   1e3 * std::sqrt(e.mean_square_m2), 100 * e.nearest_score_m, e.seconds);
      } else {
        fmt::print("  eval {:4d}{}  failed: {}\n", ++count, values, e.failure);
      }
      std::fflush(stdout);
    };
  }

  std::vector<IdentificationResult> results;
  if (a.method == "paper" || a.method == "both") {
    IsresOptions options;
    options.seed = a.seed;
    if (a.max_evaluations > 0) options.max_evaluations = a.max_evaluations;
    results.push_back(identify_isres(problem, options));
  }
  if (a.method == "gradient" || a.method == "both") {
    GradientOptions options;
    if (a.max_evaluations > 0) options.max_evaluations = a.max_evaluations;
    options.optimizer = optimizer_from_name(a.optimizer);
    results.push_back(identify_gradient(problem, options));
  }
  int status = 2;
  for (IdentificationResult& r : results) {
    // A search none of whose simulations succeeded has only its start to show: nothing to
    // report or write.
    if (r.coordinates.size() == 0 || !std::isfinite(r.objective)) {
      fmt::print("\n{}: no result ({})\n", r.method, r.stop_reason);
      if (r.coordinates.size() == 0) continue;
      for (auto& evaluator : train) {  // why: the first failure of each training trial
        const TrialFit fit = evaluator->evaluate(r.material, parameters);
        if (!fit.usable()) fmt::print("  train {}: simulation failed: {}\n", evaluator->trial().directory, fit.failure);
      }
      continue;
    }
    // The twin's discretisation error at this resolution: reported beside the residual, and the
    // part the residual holds widens the intervals by the shift it makes.
    std::optional<DiscretisationCheck> check;
    VecX held;
    if (a.discretisation_check) {
      check = check_discretisation(training, mesh, r.material, parameters);
      if (check->usable() && check->error_pattern_m.size() > 0)
        held = std::max(0.0, check->pattern_in_residual) * check->error_pattern_m;
    }
    estimate_uncertainty(problem, r, IntervalKind::kFisherOrBlocks, held.size() > 0 ? &held : nullptr);
    print_estimates(r);
    std::vector<Row> rows;
    const bool last = &r == &results.back();
    auto score = [&](const std::string& set, std::vector<std::unique_ptr<TrialEvaluator>>& evaluators) {
      for (auto& evaluator : evaluators) {
        // Test trials are simulated afresh for every method's result: continued from another
        // method's equilibria they could stay on that method's branches (with --method both, the
        // second result's test error depended on the first's: 1.09 against 0.78 cm).
        if (set == "test") evaluator->clear_warm_starts();
        const TrialFit fit = evaluator->evaluate(r.material, parameters);
        if (!fit.usable()) {
          fmt::print("  {} {}: simulation failed: {}\n", set, evaluator->trial().directory, fit.failure);
          continue;
        }
        const std::vector<Row> more = score_rows(set, *evaluator, fit);
        rows.insert(rows.end(), more.begin(), more.end());
        if (last && !a.residuals.empty()) {
          write_residual_files((std::filesystem::path(a.residuals) / set / more.back().trial).string(), *evaluator, fit);
        }
      }
    };
    score("train", train);
    score("test", test);
    print_table(base.name.substr(0, base.name.find(' ')), r.method.substr(0, r.method.find(':')), rows);
    if (last) {
      if (check) fmt::print("discretisation  {}\n", describe(*check, "at the fitted material"));
      write_material_file(a.out, r.material);
      fmt::print("\nwrote {} ({})\n", a.out, r.method);
      if (!a.residuals.empty()) fmt::print("wrote residual files under {}\n", a.residuals);
      status = 0;
    }
  }
  return status;
}

}  // namespace twin_cli
