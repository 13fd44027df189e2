#include "tests/support/finite_difference.h"

#include <algorithm>
#include <sstream>

namespace twin::testing {

std::string DerivativeErrors::report() const {
  std::ostringstream s;
  s << "relative error: gradient " << gradient << ", Hessian " << hessian;
  return s.str();
}

DerivativeErrors finite_difference_errors(const EnergyFunction& f, const Eigen::VectorXd& x,
                                          double step, double gradient_floor,
                                          double hessian_floor) {
  const int n = static_cast<int>(x.size());
  Eigen::VectorXd grad(n);
  Eigen::MatrixXd hess(n, n);
  f(x, &grad, &hess);

  Eigen::VectorXd grad_fd(n);
  Eigen::MatrixXd hess_fd(n, n);
  Eigen::VectorXd xp = x, xm = x, gp(n), gm(n);
  for (int i = 0; i < n; ++i) {
    xp(i) = x(i) + step;
    xm(i) = x(i) - step;
    const double ep = f(xp, &gp, nullptr);
    const double em = f(xm, &gm, nullptr);
    grad_fd(i) = (ep - em) / (2.0 * step);
    hess_fd.col(i) = (gp - gm) / (2.0 * step);
    xp(i) = xm(i) = x(i);
  }
  DerivativeErrors errors;
  errors.gradient = (grad_fd - grad).norm() / std::max(grad.norm(), gradient_floor);
  errors.hessian = (hess_fd - hess).norm() / std::max(hess.norm(), hessian_floor);
  return errors;
}

}  // namespace twin::testing
