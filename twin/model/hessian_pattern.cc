#include "twin/model/hessian_pattern.h"

#include <algorithm>

namespace twin {

HessianPattern::HessianPattern(const DofMap& dofs, const std::vector<TermStencil>& terms) {
  const int nf = dofs.free_vertex_count();
  // Free vertices coupled to each free column vertex J, at or above it (I <= J).
  std::vector<std::vector<int>> above(nf);
  for (int j = 0; j < nf; ++j) above[j].push_back(j);
  for (const TermStencil& term : terms) {
    const std::vector<int>& ev = *term.element_vertices;
    for (std::size_t base = 0; base + term.arity <= ev.size(); base += term.arity) {
      for (int a = 0; a < term.arity; ++a) {
        for (int b = 0; b < term.arity; ++b) {
          const int i = dofs.free_index(ev[base + a]), j = dofs.free_index(ev[base + b]);
          if (i >= 0 && j >= 0 && i < j) above[j].push_back(i);
        }
      }
    }
  }
  for (auto& list : above) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }

  // Compressed columns: column 3J+k holds the three rows of every block above the diagonal,
  // then rows 3J..3J+k of the diagonal block.
  const int n = 3 * nf;
  std::vector<int> outer(n + 1, 0);
  for (int j = 0; j < nf; ++j) {
    const int off_diagonal = static_cast<int>(above[j].size()) - 1;
    for (int k = 0; k < 3; ++k) outer[3 * j + k + 1] = outer[3 * j + k] + 3 * off_diagonal + k + 1;
  }
  matrix_.resize(n, n);
  matrix_.resizeNonZeros(outer[n]);
  std::copy(outer.begin(), outer.end(), matrix_.outerIndexPtr());
  int* inner = matrix_.innerIndexPtr();
  for (int j = 0; j < nf; ++j) {
    for (int k = 0; k < 3; ++k) {
      int p = outer[3 * j + k];
      for (int i : above[j]) {
        const int rows = i < j ? 3 : k + 1;
        for (int r = 0; r < rows; ++r) inner[p++] = 3 * i + r;
      }
    }
  }
  set_zero();

  // Value index of row 3I in column 3J+k, for I <= J.
  auto start = [&](int i, int j, int k) {
    const auto& list = above[j];
    const int pos = static_cast<int>(std::lower_bound(list.begin(), list.end(), i) - list.begin());
    return outer[3 * j + k] + 3 * pos;
  };
  slots_.resize(terms.size());
  for (std::size_t t = 0; t < terms.size(); ++t) {
    const int arity = terms[t].arity;
    const std::vector<int>& ev = *terms[t].element_vertices;
    const std::size_t elements = ev.size() / arity;
    std::vector<int>& slots = slots_[t];
    slots.assign(elements * pairs(arity) * 3, -1);
    for (std::size_t e = 0; e < elements; ++e) {
      int* s = slots.data() + e * pairs(arity) * 3;
      for (int a = 0; a < arity; ++a) {
        for (int b = a; b < arity; ++b, s += 3) {
          const int i = dofs.free_index(ev[e * arity + a]), j = dofs.free_index(ev[e * arity + b]);
          if (i < 0 || j < 0) continue;
          const bool transposed = i > j;
          for (int k = 0; k < 3; ++k) {
            s[k] = 2 * (transposed ? start(j, i, k) : start(i, j, k)) + (transposed ? 1 : 0);
          }
        }
      }
    }
  }
}

void HessianPattern::set_zero() {
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
}

}  // namespace twin
