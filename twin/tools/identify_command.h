#pragma once
// `twin identify`: material parameters from scanned trials (docs/identification.md).

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "twin/trials/trial.h"

namespace twin_cli {

struct IdentifyArguments {
  std::vector<std::string> train, test;
  std::string out;                 // material file to write
  std::string method = "gradient";  // gradient | paper | both
  std::string optimizer = "lm";     // for gradient: lm | lbfgs
  std::string parameters = "tensile_N_m,shear_N_m,bending_Nm";
  std::string start;               // optional material file: start values and fixed properties
  std::string bending_model;       // hinge | plate; empty: the start material's
  std::string membrane_model = "linear";  // linear | quadratic (trial.h: TwinMeshSpec)
  std::string residuals;           // optional directory for per-marker residual files
  int triangles = 1500;
  // --clamp-refinement (clamp_refinement_option.h): "jaws" refines near each clamp until its
  // jaws are resolved; radii (m), one refinement level each, near every clamp; "none".
  std::string clamp_refinement = "jaws";
  // --path-triangles: the coarse mesh a fresh simulation follows the clamps' path on (trial.h:
  // TwinMeshSpec::path_triangles); 0 follows it on the twin.
  int path_triangles = twin::TwinMeshSpec{}.path_triangles;
  unsigned seed = 1;
  int max_evaluations = 0;         // 0: the method's default
  bool quiet = false;
  // The fitted material also simulated on a twin of twice the triangles: how far the predicted
  // markers move is the twin's discretisation error at this resolution, reported beside the
  // residual (the noise cannot be told from it otherwise).
  bool discretisation_check = true;
};

// Adds the subcommand and its options to `app`; returns it (to test whether it was chosen).
CLI::App* add_identify_command(CLI::App& app, IdentifyArguments& arguments);

// Runs it. Exit status: 0 done, 1 bad input (the message names file and field), 2 no
// identification succeeded (nothing written).
int run_identify(const IdentifyArguments& arguments);

}  // namespace twin_cli
