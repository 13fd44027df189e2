#pragma once
// The --clamp-refinement option of `twin identify` and `twin diagnose`: "none"; "jaws" (refine
// near each clamp until its jaws are resolved, twin/trial.h: jaw_refinement_radii_m); or
// comma-separated radii (m), one refinement level each near every clamp (TwinMeshSpec).

#include <string>
#include <vector>

namespace twin_cli {

struct ClampRefinement {
  std::vector<double> radii_m;
  bool resolve_jaws = false;
};

// Throws std::invalid_argument naming the option and the bad item.
ClampRefinement parse_clamp_refinement(const std::string& value);

}  // namespace twin_cli
