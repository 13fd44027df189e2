#pragma once
// One term of the sheet's total energy (membrane, bending, gravity, inertia, viscosity).
//
// A term is a sum over elements of `arity` vertices each. It reports its elements' vertices (for
// the Hessian's sparsity pattern) and evaluates energy, gradient and Hessian over all elements.
// Terms own no positions: x is the stacked 3n vector of world positions (m).

#include <string_view>
#include <vector>

#include "twin/model/element_coloring.h"
#include "twin/model/hessian_pattern.h"
#include "twin/base/types.h"

namespace twin {

// Where a term adds its Hessian: the shared pattern and the term's index in it.
struct HessianTarget {
  HessianPattern* pattern = nullptr;
  int term = 0;
};

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;
  virtual std::string_view name() const = 0;
  virtual int arity() const = 0;
  // `arity()` vertex ids per element.
  virtual const std::vector<int>& element_vertices() const = 0;
  // Energy (J) at x. Adds the gradient (J/m = N) into *grad (size 3n) and the Hessian (N/m)
  // into the target when non-null.
  virtual double evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                          HessianMode mode) const = 0;
};

// Base for terms whose elements are independent: runs the element loop colour by colour, in
// parallel within a colour (OpenMP), gathering element positions and scattering results.
template <int A>
class ElementTerm : public EnergyTerm {
 public:
  using ElementVector = Eigen::Matrix<double, 3 * A, 1>;
  using ElementMatrix = Eigen::Matrix<double, 3 * A, 3 * A>;

  int arity() const final { return A; }
  const std::vector<int>& element_vertices() const final { return vertices_; }
  int element_count() const { return static_cast<int>(vertices_.size()) / A; }

  double evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                  HessianMode mode) const final;

 protected:
  // Must be called by the derived constructor once its elements are known.
  void set_elements(std::vector<int> vertices, int vertex_count) {
    vertices_ = std::move(vertices);
    coloring_ = color_elements(vertices_, A, vertex_count);
  }
  // Energy of element e at its positions xe; writes g and h when non-null.
  virtual double element_energy(int e, const ElementVector& xe, ElementVector* g,
                                ElementMatrix* h, HessianMode mode) const = 0;

 private:
  std::vector<int> vertices_;
  ElementColoring coloring_;
};

template <int A>
double ElementTerm<A>::evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                                HessianMode mode) const {
  double energy = 0.0;
  for (int c = 0; c < coloring_.color_count(); ++c) {
    const int begin = coloring_.color_offsets[c], end = coloring_.color_offsets[c + 1];
#pragma omp parallel for reduction(+ : energy) schedule(static)
    for (int i = begin; i < end; ++i) {
      const int e = coloring_.order[i];
      const int* v = &vertices_[A * e];
      ElementVector xe, ge;
      ElementMatrix he;
      for (int k = 0; k < A; ++k) xe.template segment<3>(3 * k) = x.segment<3>(3 * v[k]);
      energy += element_energy(e, xe, grad ? &ge : nullptr, hess ? &he : nullptr, mode);
      if (grad) {
        for (int k = 0; k < A; ++k) grad->segment<3>(3 * v[k]) += ge.template segment<3>(3 * k);
      }
      if (hess) hess->pattern->add<A>(hess->term, e, he);
    }
  }
  return energy;
}

}  // namespace twin
