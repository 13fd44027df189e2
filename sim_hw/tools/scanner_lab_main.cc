// scanner_lab: makes a scanned trial the way the paper's experiment did (sim_hw/scanner_lab.h).
//   scanner_lab --specimen composite --seed 1 --out trials/composite_1 [--truth DIR]
// The truth (material, noise-free markers) goes to DIR (default: OUT.truth), outside the trial.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include <fmt/format.h>

#include "sim_hw/scanner_lab.h"
#include "twin/material.h"

int main(int argc, char** argv) {
  CLI::App app{"Scanner lab: simulated scanned trials of a clamped sheet (paper section 4.2)"};
  sim_hw::ScannerLabConfig config;
  std::string out, truth, material_file;
  app.add_option("--specimen", config.specimen, "composite, cloth, canvas or felt");
  app.add_option("--seed", config.seed, "random seed (clamp places, moves, noise)");
  app.add_option("--out", out, "trial directory to write")->required();
  app.add_option("--truth", truth, "directory for the truth (default: OUT.truth)");
  app.add_option("--material-file", material_file, "the lab's true material (default: the specimen's)");
  app.add_option("--reference-triangles", config.reference_triangles, "triangles of the reference sheet");
  app.add_option("--marker-noise-m", config.marker_noise_m, "marker position noise, 1 sigma per axis (m)");
  app.add_flag("!--no-scans", config.raw_scans, "do not write raw scan points");
  CLI11_PARSE(app, argc, argv);
  try {
    if (!material_file.empty()) config.material_override = twin::read_material_file(material_file);
    const sim_hw::LabTrial lab = sim_hw::make_lab_trial(config);
    if (truth.empty()) truth = out + ".truth";
    sim_hw::write_lab_trial(lab, config, out, truth);
    int hidden = 0;
    for (const auto& stage : lab.trial.stages) hidden += static_cast<int>(stage.observed.markers_m.size()) - stage.observed.seen_marker_count();
    fmt::print("scanner lab: {} seed {}: {} stages, {} markers, {} hidden under clamps in all -> {} (truth in {})\n",
               config.specimen, config.seed, lab.trial.stages.size(), lab.trial.marker_uv_m.size(), hidden, out, truth);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scanner_lab: %s\n", e.what());
    return 2;
  }
}
