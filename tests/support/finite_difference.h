#pragma once
// One finite-difference checker for every energy of the twin (after Ceres' GradientChecker):
// central differences of the energy give the gradient, central differences of the analytic
// gradient give the Hessian, and both are compared with the analytic ones in a relative norm.

#include <functional>
#include <string>

#include <Eigen/Core>

namespace twin::testing {

// Evaluates energy at x; fills grad (same size as x) and hess (square) when non-null.
using EnergyFunction =
    std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd* grad, Eigen::MatrixXd* hess)>;

struct DerivativeErrors {
  double gradient = 0.0;  // ||g_fd - g|| / max(||g||, floor)
  double hessian = 0.0;   // ||H_fd - H||_F / max(||H||_F, floor)
  std::string report() const;
};

// step: central-difference step in the units of x (about 1e-6 of its scale works for positions
// in metres). Absolute floors keep the ratio finite where the true derivative vanishes.
DerivativeErrors finite_difference_errors(const EnergyFunction& f, const Eigen::VectorXd& x,
                                          double step, double gradient_floor = 1e-12,
                                          double hessian_floor = 1e-12);

}  // namespace twin::testing
