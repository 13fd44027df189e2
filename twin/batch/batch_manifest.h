#pragma once
// What `twin batch` characterises: many materials, each with its training and held-out trial
// directories, diagnosed (twin/diagnosis/diagnose.h) with one set of options. Manifest file
// (JSON; relative paths are relative to it):
//   {"materials": [{"name": "composite_lot7",            (letters, digits, '.', '_', '-'; unique:
//                                                         the output sub-directory)
//                   "train": ["trials/lot7_a", ...],      (trial directories, twin/trials/trial.h)
//                   "test": ["trials/lot7_b"],
//                   "material": "composite_start.json"},  (optional start material)
//                  ...],
//    "diagnose": {"triangles": 300, "path_triangles": 300, "refits": 3,   (all optional; as the
//                 "effects": "orthotropic_stiffness,...", "noise_mm": 0.3,  `twin diagnose`
//                 "optimizer": "lm", "discretisation_check": true}}         options of that name)
// Errors throw std::invalid_argument naming the file and the field; a trial directory that does
// not exist is an error here, before anything runs.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "twin/diagnosis/diagnose.h"

namespace twin::batch {

struct BatchMaterial {
  std::string name;
  std::vector<std::string> train, test;  // absolute or relative to the working directory
  std::string material;                  // optional start material file
  // The entry as written, with the diagnose options: a finished material is redone when this
  // changed since (batch_runner.h).
  std::string fingerprint;
};

struct BatchManifest {
  std::string source;
  std::vector<BatchMaterial> materials;
  diagnosis::DiagnoseOptions diagnose;  // train, test, material and report are per material
};

BatchManifest batch_manifest_from_json(const nlohmann::json& j, const std::string& source,
                                       const std::string& base_directory);
// Also throws std::runtime_error when the file cannot be read or is not JSON.
BatchManifest read_batch_manifest(const std::string& path);

}  // namespace twin::batch
