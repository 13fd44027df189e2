#pragma once
// The scanner lab as the identification and diagnosis tests use it: the composite on a uniform
// reference mesh of `triangles` (the kind the twin uses, so the twin can match it to the noise;
// the lab's own default resolves the jaws, sim_hw/scanner_lab.h), no raw scans (faster).

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
