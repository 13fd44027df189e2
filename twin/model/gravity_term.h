#pragma once
// Potential energy of the sheet's weight: E = -sum_i m_i g . x_i (J), with lumped vertex masses
// m_i (kg) and gravity g (m/s^2, default -9.80665 along world z). Linear in x: no Hessian.

#include "twin/model/energy_term.h"

namespace twin {

class GravityTerm final : public EnergyTerm {
 public:
  GravityTerm(std::vector<double> vertex_masses_kg, const Vec3& gravity_m_s2);
  std::string_view name() const override { return "gravity"; }
  int arity() const override { return 1; }
  const std::vector<int>& element_vertices() const override { return vertices_; }
  double evaluate(const VecX& x, VecX* grad, const HessianTarget* hess,
                  HessianMode mode) const override;

  void set_masses(std::vector<double> vertex_masses_kg) { masses_ = std::move(vertex_masses_kg); }
  const Vec3& gravity() const { return gravity_; }

 private:
  std::vector<double> masses_;
  std::vector<int> vertices_;
  Vec3 gravity_;
};

}  // namespace twin
