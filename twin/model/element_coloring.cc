#include "twin/model/element_coloring.h"

#include <algorithm>

namespace twin {

ElementColoring color_elements(const std::vector<int>& element_vertices, int arity,
                               int vertex_count) {
  const int elements = arity > 0 ? static_cast<int>(element_vertices.size()) / arity : 0;
  std::vector<std::vector<int>> colors_at(vertex_count);  // colours touching each vertex
  std::vector<int> color(elements);
  std::vector<char> taken;
  int colors = 0;
  for (int e = 0; e < elements; ++e) {
    taken.assign(colors + 1, 0);
    for (int k = 0; k < arity; ++k) {
      for (int c : colors_at[element_vertices[arity * e + k]]) taken[c] = 1;
    }
    const int c = static_cast<int>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    color[e] = c;
    colors = std::max(colors, c + 1);
    for (int k = 0; k < arity; ++k) colors_at[element_vertices[arity * e + k]].push_back(c);
  }
  ElementColoring result;
  result.color_offsets.assign(colors + 1, 0);
  for (int e = 0; e < elements; ++e) ++result.color_offsets[color[e] + 1];
  for (int c = 0; c < colors; ++c) result.color_offsets[c + 1] += result.color_offsets[c];
  result.order.resize(elements);
  std::vector<int> next(result.color_offsets.begin(), result.color_offsets.end() - 1);
  for (int e = 0; e < elements; ++e) result.order[next[color[e]]++] = e;
  return result;
}

}  // namespace twin
