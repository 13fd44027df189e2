#pragma once
// The scanner lab as the identification and diagnosis tests of the workflow use it: the
// composite simulated by the twin's own model on a uniform reference mesh of `triangles` (so
// the twin can match it to the noise: these tests check the workflow's mechanics, not the
// twin's accuracy against a sheet it does not share; the lab's default is the independent
// sheet, sim_hw/lab_reference.h), no raw scans (faster).

#include <cstdint>

#include "sim_hw/scanner_lab.h"

namespace testing_support {

inline sim_hw::ScannerLabConfig uniform_lab_config(std::uint64_t seed, int triangles) {
  sim_hw::ScannerLabConfig config;
  config.specimen = "composite";
  config.seed = seed;
  config.reference_triangles = triangles;
  config.truth_model = sim_hw::TruthModel::kTwin;  // the workflow against its own model
  config.reference_resolves_jaws = false;
  config.raw_scans = false;
  return config;
}

}  // namespace testing_support
