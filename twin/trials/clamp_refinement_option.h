#pragma once
// The --clamp-refinement option of `twin identify` and `twin diagnose` (and the scanner lab's
// --reference-clamp-refinement): "none"; "jaws" (refine near each clamp until its jaws are
// resolved, twin/trials/trial.h: jaw_refinement_radii_m); or comma-separated radii (m), one refinement
// level each near every clamp (TwinMeshSpec).

#include <string>
#include <vector>

namespace twin {

struct ClampRefinement {
  std::vector<double> radii_m;
  bool resolve_jaws = false;
};

// `option` names the option in messages. Throws std::invalid_argument naming it and the bad item.
ClampRefinement parse_clamp_refinement(const std::string& value, const std::string& option = "--clamp-refinement");

}  // namespace twin
