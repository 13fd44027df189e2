#include "twin/trials/clamp_refinement_option.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace twin {

ClampRefinement parse_clamp_refinement(const std::string& value, const std::string& option) {
  if (value == "none") return {};
  if (value == "jaws") return {{}, true};
  std::vector<double> radii;
  std::stringstream in(value);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double r = NAN;
    try {
      r = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(r) || r <= 0.0) {
      throw std::invalid_argument(fmt::format(
          "{}: expected 'jaws', 'none' or comma-separated radii > 0 (m), got '{}'", option, item));
    }
    radii.push_back(r);
  }
  if (radii.empty()) throw std::invalid_argument(option + ": expected 'jaws', 'none' or radii > 0 (m), got nothing");
  return {radii, false};
}

}  // namespace twin
