// diagnose_cell_log: the "find" step of the discrepancy workflow (issue 6) on a running cell.
// From an lcm-logger log of a cell run it takes, per cycle, the tracked sheet and the twin's
// prediction, and reports where they disagree beyond the tracking noise: chi-square per cycle
// and per region, and the structure over material direction, clamp distance, curvature, load
// and the time since a clamp moved (twin/diagnosis/cycle_residuals.h). Exit status: 0 (whatever
// was found), 1 bad input.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cell/cell_config.h"
#include "cell/cell_log_cycles.h"
#include "twin/base/atomic_file.h"
#include "twin/diagnosis/diagnosis_report.h"
#include "twin/diagnosis/noise_estimate.h"
#include "twin/diagnosis/residual_analysis.h"
#include "twin/trials/grasp_plan.h"

namespace dx = twin::diagnosis;

namespace {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// OUT/cycles.json: one row per analysed cycle.
nlohmann::json cycles_json(const dx::ResidualField& field, const dx::ResidualAnalysis& analysis,
                           const std::vector<dx::SheetCycle>& cycles) {
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t s = 0; s < field.stages.size(); ++s) {
    const dx::FieldStage& st = field.stages[s];
    const dx::ChiSquareTest& t = analysis.stages[s].test;
    int regions = 0;
    for (const dx::RegionResult& r : analysis.stages[s].regions) regions += r.test.significant ? 1 : 0;
    rows.push_back({{"cycle", cycles[static_cast<std::size_t>(st.trial_stage)].cycle_id},
                    {"time_s", cycles[static_cast<std::size_t>(st.trial_stage)].time_s},
                    {"age_s", finite_or_null(st.age_s)},
                    {"load_m", st.load_m},
                    {"vertices", st.samples},
                    {"mean_error_mm", 1e3 * st.mean_error_m},
                    {"rms_mm", 1e3 * t.rms_m},
                    {"chi_square", t.chi_square},
                    {"dof", t.dof},
                    {"p_value", t.p_value},
                    {"significant", t.significant},
                    {"significant_regions", regions}});
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Find where the twin and the tracked sheet of a cell run disagree: per cycle and per region "
      "against the tracking noise, with the structure of the disagreement."};
  std::string log_path, config_path, report_dir;
  double noise_mm = 0.0;
  int max_cycles = 60;
  app.add_option("LOG", log_path, "lcm-logger log of a cell run (SHEET_OBSERVED, SHEET_PREDICTED)")->required();
  app.add_option("--config", config_path, "the run's cell config (its sheet mesh and grasp plan)")->required();
  app.add_option("--report", report_dir, "output directory (report.md, figures/, cycles.json)")->required();
  app.add_option("--noise-mm", noise_mm,
                 "tracking noise per coordinate (mm); default: estimated from the residuals")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-cycles", max_cycles, "analyse at most this many cycles, evenly spread (default 60)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  try {
    const cell::CellConfig config = cell::read_cell_config(config_path);
    const twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
    const twin::SheetMesh& mesh = config.sheet.mesh;
    const cell::LoggedCycles logged = cell::read_logged_cycles(log_path, mesh.vertex_count());
    const std::string read = fmt::format(
        "{} observed and {} predicted sheets read; {} cycles paired, {} unpaired, {} on another mesh, {} "
        "undecodable; {} run(s)",
        logged.observed, logged.predicted, logged.cycles.size(), logged.unpaired, logged.other_mesh,
        logged.undecodable, logged.runs);
    if (logged.cycles.empty()) {
      throw std::invalid_argument(fmt::format("{}: no cycle with both sheets on the config's mesh ({} vertices, {}): {}",
                                              log_path, mesh.vertex_count(), config_path, read));
    }
    const std::vector<std::size_t> selected =
        dx::spread_cycles(logged.cycles.size(), static_cast<std::size_t>(max_cycles));
    dx::ResidualField field;
    const std::string name = std::filesystem::path(log_path).stem().string();
    dx::add_cycle_residuals(field, mesh, plan.clamp_specs(), logged.cycles, name.empty() ? "log" : name, selected);
    if (field.samples.empty()) throw std::invalid_argument(log_path + ": no observed vertex in the analysed cycles");

    double sigma_m = 1e-3 * noise_mm;
    std::string noise_source;
    if (noise_mm <= 0.0) {
      const dx::NoiseEstimate noise = dx::estimate_noise(field);
      sigma_m = noise.sigma_m;
      noise_source = "the cell log's residuals (" + noise.method + ")";
    }
    const dx::ResidualAnalysis analysis = dx::analyse_residuals(field, sigma_m);

    dx::ReportData data;
    data.title = "Cell run discrepancy: twin prediction against tracked sheet";
    const int significant = analysis.significant_stage_count();
    data.verdict_line =
        significant == 0
            ? fmt::format("no cycle disagrees beyond the tracking noise ({} cycles analysed)", field.stages.size())
            : fmt::format("the twin and the tracked sheet disagree in {} of {} analysed cycles ({} regions)",
                          significant, field.stages.size(), analysis.significant_region_count());
    data.noise_floor_m = sigma_m;
    data.noise_source = noise_source;
    data.notes.push_back("each stage below is one cycle of the run (label LOG/cycle id), its markers the twin mesh's "
                         "vertices the cameras saw, its age the time since a grasp point last moved by more than 1 mm, "
                         "its load the highest grasp point's lift over the first cycle's");
    data.notes.push_back(fmt::format("log {}: {}", log_path, read));
    data.notes.push_back(fmt::format("analysed {} of {} paired cycles, evenly spread (--max-cycles {})",
                                     selected.size(), logged.cycles.size(), max_cycles));
    data.notes.push_back(fmt::format("noise sigma {:.3f} mm per coordinate ({})", 1e3 * sigma_m,
                                     noise_source.empty() ? std::string("given") : "estimated on " + noise_source));
    dx::ReportPhase phase;
    phase.name = "cell run";
    phase.before = field;
    phase.before_analysis = analysis;
    data.phases.push_back(std::move(phase));
    dx::write_report(data, report_dir);
    twin::write_file_atomically(std::filesystem::path(report_dir) / "cycles.json", [&](std::ostream& out) {
      out << nlohmann::json{{"noise_sigma_mm", 1e3 * sigma_m},
                            {"noise_estimated", !noise_source.empty()},
                            {"cycles_paired", logged.cycles.size()},
                            {"cycles", cycles_json(field, analysis, logged.cycles)}}
                 .dump(2)
          << "\n";
    });
    fmt::print("{}", dx::terminal_summary(data));
    fmt::print("wrote {}/report.md, {}/cycles.json\n", report_dir, report_dir);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "diagnose_cell_log: {}\n", e.what());
    return 1;
  }
}
