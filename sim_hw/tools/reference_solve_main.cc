// reference_solve: the reference sheet (docs/reference_sheet.md) on any trial in the documented
// format (docs/file_formats.md), made by the lab or outside it: the trial's clamps and stages
// followed by the lab's protocol on the B-spline shell at the given material, and written as a
// truth directory like the lab's (<stage>_true.xyz: every marker at the finest level; material.json;
// lab.json with the reference and its own error per stage). What the trial observed is not read.
//   reference_solve --trial T --material-file M --out T.truth [--levels 2]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/durable_file.h"
#include "sim_hw/lab_reference.h"
#include "sim_hw/shell_reference.h"
#include "twin/model/material.h"
#include "twin/trials/trial.h"

int main(int argc, char** argv) {
  CLI::App app{"The reference sheet on a trial's clamps and stages, written as a truth directory"};
  std::string trial_dir, material_file, out_dir;
  sim_hw::ReferenceSheet reference;
  reference.shell_levels = 2;
  app.add_option("--trial", trial_dir, "the trial directory")->required();
  app.add_option("--material-file", material_file, "the sheet's material (docs/file_formats.md)")->required();
  app.add_option("--out", out_dir, "the truth directory to write")->required();
  app.add_option("--levels", reference.shell_levels,
                 "bisections above level 0 (2: three levels, the observed order and Richardson's estimate)")
      ->check(CLI::Range(0, 3));
  app.add_option("--span-m", reference.shell_span_m, "level 0's largest span (m; default: for the material)");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto start = std::chrono::steady_clock::now();
    const twin::Trial trial = twin::read_trial(trial_dir);
    if (!trial.sheet.is_rectangle()) throw std::invalid_argument(trial_dir + ": the reference needs a rectangular sheet");
    const twin::Material material = twin::read_material_file(material_file);
    const sim_hw::ReferenceStages r =
        sim_hw::shell_reference(reference, material, {}, trial.sheet.width_m, trial.sheet.height_m, trial.clamps,
                                trial.stages, trial.marker_uv_m);
    std::filesystem::create_directories(out_dir);
    for (std::size_t s = 0; s < r.markers_m.size(); ++s) {
      twin::write_xyz_file((std::filesystem::path(out_dir) / (trial.stages[s].id + "_true.xyz")).string(), r.markers_m[s]);
    }
    twin::write_material_file((std::filesystem::path(out_dir) / "material.json").string(), material);
    nlohmann::json lab{{"trial", trial_dir}, {"reference", r.description}, {"shell_levels", reference.shell_levels}};
    if (!r.truth_error.empty()) lab["truth_error"] = sim_hw::truth_error_json(r.truth_error, trial.stages);
    prepreg::write_file_atomically((std::filesystem::path(out_dir) / "lab.json").string(),
                                [&](std::ostream& out) { out << lab.dump(2) << "\n"; });
    fmt::print("reference_solve: {} -> {}: {}\n", trial_dir, out_dir, r.description);
    for (std::size_t s = 0; s < r.truth_error.size(); ++s) {
      fmt::print("  stage {}: {}\n", trial.stages[s].id, r.truth_error[s].text);
    }
    fmt::print("{:.0f} s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "reference_solve: {}\n", e.what());
    return 1;
  }
}
