#pragma once
// Which vertices the solver moves. A clamped vertex is fixed in all three coordinates; the
// others are numbered 0..free_count-1 in vertex order. The unknowns of a solve are the 3
// coordinates of each free vertex, in that order.

#include <vector>

namespace twin {

class DofMap {
 public:
  DofMap() = default;
  // fixed[i] != 0 marks vertex i as held.
  explicit DofMap(const std::vector<char>& fixed);

  int vertex_count() const { return static_cast<int>(free_index_.size()); }
  int free_vertex_count() const { return free_count_; }
  int free_dof_count() const { return 3 * free_count_; }
  // -1 for a fixed vertex.
  int free_index(int vertex) const { return free_index_[vertex]; }
  bool is_fixed(int vertex) const { return free_index_[vertex] < 0; }
  const std::vector<char>& fixed_mask() const { return fixed_; }

 private:
  std::vector<char> fixed_;
  std::vector<int> free_index_;
  int free_count_ = 0;
};

}  // namespace twin
