#pragma once
// The --clamp-refinement option of `twin identify` and `twin diagnose`: "none", or
// comma-separated radii (m), one refinement level each near every clamp (twin/trial.h:
// TwinMeshSpec).

#include <string>
#include <vector>

namespace twin_cli {

// Throws std::invalid_argument naming the option and the bad item.
std::vector<double> parse_clamp_refinement(const std::string& value);

}  // namespace twin_cli
