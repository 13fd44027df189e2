#include "twin/model/dihedral_angle.h"

#include <cmath>
#include <limits>

namespace twin {
namespace {

// One wing of the hinge: triangle (x0, x1, x_free) with unit normal n. Local vertex order is
// (x0, x1, x_free); `free_slot` is the free vertex's place (2 or 3) in the 12-vector.
// In the in-plane frame (e^ along the hinge, m^ toward the free vertex):
//   x_free - x0 = s l e^ + h m^,   c = ((1 - s)/h, s/h, -1/h) = f / (2A) with f = ((1-s) l, s l, -l)
//   grad phi = (((s-1)/h) m^ - e^/l,  -(s/h) m^ + e^/l,  m^/h)
// and d f_k / d x_j (rows k, columns j) as derived from l = |e| and s:
//   d f_0 = ((h/l) m^,  e^ - (h/l) m^,  -e^)
//   d f_1 = (-e^ - (h/l) m^,  (h/l) m^,  e^)
//   d f_2 = (e^,  -e^,  0)
struct Wing {
  Vec3 n;
  double c[3];
  Vec3 grad_phi[3];
  Vec3 dc[3][3];  // dc[k][j] = d c_k / d x_j (in-plane part), 1/m^2
  int slot[3];
};

// grad_phi and dc are filled only `with_second_derivatives` (for the exact Hessian): the
// gradient needs c alone, and they were most of a gradient-only evaluation's cost.
Wing make_wing(const Vec3& x0, const Vec3& e_hat, double l, const Vec3& free_vertex,
               const Vec3& n, int free_slot, bool with_second_derivatives) {
  Wing w;
  w.n = n;
  w.slot[0] = 0;
  w.slot[1] = 1;
  w.slot[2] = free_slot;
  const Vec3 r = free_vertex - x0;
  const double s = r.dot(e_hat) / l;
  const Vec3 perp = r - s * l * e_hat;
  const double h = perp.norm();
  const Vec3 m = perp / h;
  const double two_area = l * h;
  w.c[0] = (1.0 - s) / h;
  w.c[1] = s / h;
  w.c[2] = -1.0 / h;
  if (!with_second_derivatives) return w;
  w.grad_phi[0] = ((s - 1.0) / h) * m - e_hat / l;
  w.grad_phi[1] = -(s / h) * m + e_hat / l;
  w.grad_phi[2] = m / h;
  const Vec3 hm = (h / l) * m;
  const Vec3 df[3][3] = {{hm, e_hat - hm, -e_hat}, {-e_hat - hm, hm, e_hat}, {e_hat, -e_hat, Vec3::Zero()}};
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) w.dc[k][j] = df[k][j] / two_area - w.c[k] * w.grad_phi[j];
  }
  return w;
}

}  // namespace

double dihedral_angle(const Vec12& xh, Vec12* grad, Mat12* hess) {
  const Vec3 x0 = xh.segment<3>(0), x1 = xh.segment<3>(3);
  const Vec3 x2 = xh.segment<3>(6), x3 = xh.segment<3>(9);
  const Vec3 e = x1 - x0;
  const Vec3 na = e.cross(x2 - x0);
  const Vec3 nb = (x3 - x0).cross(e);
  const double la = na.norm(), lb = nb.norm(), l = e.norm();
  if (!(la > 0.0 && lb > 0.0 && l > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const Vec3 ua = na / la, ub = nb / lb, e_hat = e / l;
  const double theta = std::atan2(ua.cross(ub).dot(e_hat), ua.dot(ub));
  if (!grad && !hess) return theta;

  const bool second = hess != nullptr;
  const Wing wings[2] = {make_wing(x0, e_hat, l, x2, ua, 2, second), make_wing(x0, e_hat, l, x3, ub, 3, second)};
  if (grad) {
    grad->setZero();
    for (const Wing& w : wings) {
      for (int k = 0; k < 3; ++k) grad->segment<3>(3 * w.slot[k]) += w.c[k] * w.n;
    }
  }
  if (hess) {
    // d(c_k n)/dx_j = n (dc_k/dx_j)^T + c_k dn/dx_j, with dn/dx_j = -grad_phi_j n^T.
    hess->setZero();
    for (const Wing& w : wings) {
      for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j) {
          hess->block<3, 3>(3 * w.slot[k], 3 * w.slot[j]) +=
              w.n * w.dc[k][j].transpose() - w.c[k] * w.grad_phi[j] * w.n.transpose();
        }
      }
    }
  }
  return theta;
}

}  // namespace twin
