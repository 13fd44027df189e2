#pragma once
// Groups elements into colours so that no two elements of a colour share a vertex; a parallel
// loop over one colour can then add into per-vertex gradient and Hessian entries without races
// or atomics. (Energies are summed by an OpenMP reduction whose order depends on the thread
// count, so results can differ in the last bits between thread counts.)

#include <vector>

namespace twin {

struct ElementColoring {
  std::vector<int> order;          // element ids grouped by colour
  std::vector<int> color_offsets;  // colour c is order[color_offsets[c] .. color_offsets[c+1])
  int color_count() const { return static_cast<int>(color_offsets.size()) - 1; }
};

// element_vertices holds `arity` vertex ids per element. Greedy first-fit colouring; any
// number of colours (a fan vertex of valence k needs k).
ElementColoring color_elements(const std::vector<int>& element_vertices, int arity,
                               int vertex_count);

}  // namespace twin
