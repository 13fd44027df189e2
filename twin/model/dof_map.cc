#include "twin/model/dof_map.h"

namespace twin {

DofMap::DofMap(const std::vector<char>& fixed) : fixed_(fixed), free_index_(fixed.size(), -1) {
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    if (!fixed[i]) free_index_[i] = free_count_++;
  }
}

}  // namespace twin
