// `twin`: command-line front end of the sheet twin.
//   twin solve SCENARIO --out DIR      equilibrium at every stage of a scenario (PLY + summary)
//   twin material FILE                 check a material file and print what the twin will use
//   twin identify --train DIR... --out FILE   material parameters from scanned trials
//   twin diagnose --train DIR... --test DIR... --report OUT   find, name and add a missing effect
//   twin batch MANIFEST --out DIR      diagnose many materials; resumes where it stopped
// Exit status: 0 success, 1 bad input (the message names the file and field), 2 a stage did
// not converge (its result is not written; later stages are skipped because they depend on it).

#include <omp.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "batch_command.h"
#include "diagnose_command.h"
#include "identify_command.h"
#include "twin/base/atomic_file.h"
#include "twin/distributed/rank_group.h"
#include "twin/mesh/mesh_io.h"
#include "twin/trials/scenario.h"

namespace {

using namespace twin;

struct StageResult {
  std::string id;
  ContinuationReport report;
  double lowest_z_m = 0.0;
  double highest_z_m = 0.0;
  std::string file;
};

int solve(const std::string& scenario_path, const std::string& out_dir, bool verbose) {
  const Scenario scenario = read_scenario_file(scenario_path);
  ShellModel model(scenario.mesh, scenario.material);
  const ClampSet clamps(model.mesh(), scenario.clamps);
  model.set_clamps_of_material_effects(clamps);
  fmt::print("scenario  {}\nsheet     {}, {} vertices, {:.3f} kg\nmaterial  {}: Y {:.4g}/{:.4g} N/m, "
             "G {:.4g} N/m, D {:.4g}/{:.4g} N*m{}, {:.4g} kg/m^2\n",
             scenario_path, scenario.mesh_description, model.vertex_count(), model.total_mass_kg(),
             model.material().name, model.material().tensile_stiffness_u_N_m,
             model.material().tensile_stiffness_v_N_m, model.material().shear_stiffness_N_m,
             model.material().bending_rigidity_u_Nm, model.material().bending_rigidity_v_Nm,
             model.material().bending_given_as_modulus() ? " (from modulus)" : "",
             model.material().surface_density_kg_m2);
  create_directories_durably(out_dir);

  QuasiStaticSolver solver(model, clamps);
  ContinuationOptions options = scenario.solver;
  if (verbose) {
    options.newton.on_iteration = [](const NewtonIteration& it) {
      fmt::print("    iteration {:3d}  residual {:.2e}  step {:.2e} m{}\n", it.iteration,
                 it.residual, it.largest_move_m, it.exact_hessian ? "  (exact Hessian)" : "");
    };
  }
  VecX x = place_flat(model.mesh(), scenario.placement);
  std::vector<ClampPose> poses(clamps.size());
  for (ClampPose& p : poses) p.engaged = false;

  fmt::print("\n{:<8} {:<10} {:>10} {:>8} {:>10} {:>10} {:>10}  {}\n", "stage", "status",
             "increments", "Newton", "time ms", "lowest m", "highest m", "file");
  std::vector<StageResult> results;
  int status = 0;
  for (const Stage& stage : scenario.stages) {
    StageResult r;
    r.id = stage.id;
    r.report = solver.move(poses, stage.poses, x, options);
    if (!r.report.usable()) {
      fmt::print("{:<8} {:<10} {:>10} {:>8} {:>10.1f}  -- {}\n", stage.id, "FAILED",
                 r.report.increments, r.report.newton_iterations, 1e3 * r.report.seconds,
                 r.report.last.brief());
      results.push_back(r);
      status = 2;
      break;
    }
    poses = stage.poses;
    r.lowest_z_m = 1e300;
    r.highest_z_m = -1e300;
    for (int i = 0; i < model.vertex_count(); ++i) {
      r.lowest_z_m = std::min(r.lowest_z_m, x(3 * i + 2));
      r.highest_z_m = std::max(r.highest_z_m, x(3 * i + 2));
    }
    r.file = (std::filesystem::path(out_dir) / ("stage_" + stage.id + ".ply")).string();
    write_ply(r.file, surface_from_positions(model.mesh(), x));
    fmt::print("{:<8} {:<10} {:>10} {:>8} {:>10.1f} {:>10.4f} {:>10.4f}  {}\n", stage.id,
               "converged", r.report.increments, r.report.newton_iterations,
               1e3 * r.report.seconds, r.lowest_z_m, r.highest_z_m, r.file);
    results.push_back(r);
  }

  nlohmann::json summary;
  summary["scenario"] = scenario_path;
  summary["sheet"] = scenario.mesh_description;
  summary["vertices"] = model.vertex_count();
  summary["triangles"] = model.mesh().triangle_count();
  for (const StageResult& r : results) {
    nlohmann::json s;
    s["id"] = r.id;
    s["status"] = r.report.usable() ? "converged" : to_string(r.report.last.status);
    s["increments"] = r.report.increments;
    s["newton_iterations"] = r.report.newton_iterations;
    s["residual"] = r.report.last.residual;
    s["seconds"] = r.report.seconds;
    if (r.report.usable()) {
      s["lowest_z_m"] = r.lowest_z_m;
      s["highest_z_m"] = r.highest_z_m;
      s["mesh"] = r.file;
    } else {
      s["message"] = r.report.last.brief();
    }
    summary["stages"].push_back(s);
  }
  write_file_atomically(std::filesystem::path(out_dir) / "summary.json",
                        [&](std::ostream& out) { out << summary.dump(2) << "\n"; });
  fmt::print("\nsummary   {}\n", (std::filesystem::path(out_dir) / "summary.json").string());
  return status;
}

int describe_material(const std::string& path) {
  const Material m = read_material_file(path);
  fmt::print("{}\n", material_to_json(m).dump(2));
  fmt::print("bending rigidity used: weft {:.6g} N*m, warp {:.6g} N*m{}\n", m.bending_rigidity_u_Nm,
             m.bending_rigidity_v_Nm,
             m.bending_given_as_modulus() ? " (converted from the modulus: D = E t^3 / (12 (1 - nu^2)))" : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Digital twin of a hanging prepreg or fabric sheet"};
  app.require_subcommand(1);
  int threads = 0;
  app.add_option("--threads", threads, "worker threads (default: all cores)")->check(CLI::NonNegativeNumber);

  std::string scenario, out_dir = "out";
  bool verbose = false;
  CLI::App* solve_cmd = app.add_subcommand("solve", "static equilibrium at every stage of a scenario");
  solve_cmd->add_option("scenario", scenario, "scenario file (JSON)")->required();
  solve_cmd->add_option("--out", out_dir, "output folder for stage_<id>.ply and summary.json");
  solve_cmd->add_flag("--verbose", verbose, "print every Newton iteration");

  std::string material;
  CLI::App* material_cmd = app.add_subcommand("material", "check a material file and show the values used");
  material_cmd->add_option("file", material, "material file (JSON)")->required();

  twin_cli::IdentifyArguments identify;
  CLI::App* identify_cmd = twin_cli::add_identify_command(app, identify);

  twin_cli::DiagnoseArguments diagnose;
  CLI::App* diagnose_cmd = twin_cli::add_diagnose_command(app, diagnose);

  twin_cli::BatchArguments batch;
  CLI::App* batch_cmd = twin_cli::add_batch_command(app, batch);

  CLI11_PARSE(app, argc, argv);
  if (threads > 0) omp_set_num_threads(threads);
  try {
    // Only the batch and the diagnosis spread their work over ranks; any other command under
    // mpirun -np N would run N times into the same files.
    int ranks = 1;
    if (!*batch_cmd && !*diagnose_cmd && twin::distributed::launched_by_mpirun(&ranks) && ranks > 1) {
      throw std::runtime_error(fmt::format("started by mpirun with {} ranks: of the twin's commands only 'batch' and "
                                           "'diagnose' run over MPI ranks; run this one without mpirun",
                                           ranks));
    }
    if (*solve_cmd) return solve(scenario, out_dir, verbose);
    if (*material_cmd) return describe_material(material);
    if (*identify_cmd) return twin_cli::run_identify(identify);
    if (*diagnose_cmd) return twin_cli::run_diagnose(diagnose);
    if (*batch_cmd) return twin_cli::run_batch_command(batch);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
