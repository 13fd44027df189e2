// The reference shell against the continuum: the bending energy of surfaces interpolated onto
// the spline space (cylinders bent along five directions, a twist, a saddle, a dome) converges
// to the plate energy 1/2 int k^T D k dA of the exact surface at the order the space promises,
// printed per surface; a cantilever under its own weight converges to Euler-Bernoulli's tip
// deflection q L^4 / (8 D).

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include <catch2/catch.hpp>

#include "sim_hw/real_sheet/kirchhoff_love_point.h"
#include "sim_hw/spline_shell/shell_equilibrium.h"
#include "tests/sim_hw/spline_shell/shell_fixtures.h"

namespace ss = sim_hw::spline_shell;
namespace rs = sim_hw::real_sheet;

namespace {

constexpr double kW = 0.2, kH = 0.15;

// A surface given with its derivatives: y = (x_uu, x_vv, x_uv, x_u, x_v) at a material point.
struct Surface {
  std::string name;
  std::function<ss::Vec3(const ss::Vec2&)> position;
  std::function<rs::Vec15(const ss::Vec2&)> derivatives;
};

// The isometric cylinder of radius R whose curvature runs along direction theta (from u), its
// axis through the sheet's centre.
Surface cylinder(double theta_deg, double R) {
  const double t = theta_deg * std::numbers::pi / 180.0;
  const ss::Vec3 across(std::cos(t), std::sin(t), 0.0), along(-std::sin(t), std::cos(t), 0.0), up(0, 0, 1);
  const ss::Vec2 c(0.5 * kW, 0.5 * kH);
  const auto s_of = [=](const ss::Vec2& uv) { return (uv - c).dot(ss::Vec2(std::cos(t), std::sin(t))); };
  const auto r_of = [=](const ss::Vec2& uv) { return (uv - c).dot(ss::Vec2(-std::sin(t), std::cos(t))); };
  Surface s;
  s.name = "cylinder along " + std::to_string(static_cast<int>(theta_deg)) + " deg";
  s.position = [=](const ss::Vec2& uv) {
    const double a = s_of(uv) / R;
    return ss::Vec3(R * std::sin(a) * across + r_of(uv) * along + R * (1.0 - std::cos(a)) * up);
  };
  s.derivatives = [=](const ss::Vec2& uv) {
    const double a = s_of(uv) / R;
    const ss::Vec3 xs = std::cos(a) * across + std::sin(a) * up, xss = (-std::sin(a) * across + std::cos(a) * up) / R;
    const ss::Vec2 ds(std::cos(t), std::sin(t)), dr(-std::sin(t), std::cos(t));
    rs::Vec15 y;
    y.segment<3>(0) = xss * ds.x() * ds.x();
    y.segment<3>(3) = xss * ds.y() * ds.y();
    y.segment<3>(6) = xss * ds.x() * ds.y();
    y.segment<3>(9) = xs * ds.x() + along * dr.x();
    y.segment<3>(12) = xs * ds.y() + along * dr.y();
    return y;
  };
  return s;
}

// z = (a u'^2 + 2 b u' v' + c v'^2) / 2 about the centre: a dome (a = c), a saddle (a = -c), a twist (b).
Surface quadric(const std::string& name, double a, double b, double c) {
  const ss::Vec2 o(0.5 * kW, 0.5 * kH);
  Surface s;
  s.name = name;
  s.position = [=](const ss::Vec2& uv) {
    const ss::Vec2 d = uv - o;
    return ss::Vec3(uv.x(), uv.y(), 0.5 * (a * d.x() * d.x() + 2 * b * d.x() * d.y() + c * d.y() * d.y()));
  };
  s.derivatives = [=](const ss::Vec2& uv) {
    const ss::Vec2 d = uv - o;
    rs::Vec15 y;
    y << 0, 0, a, 0, 0, c, 0, 0, b, 1, 0, a * d.x() + b * d.y(), 0, 1, b * d.x() + c * d.y();
    return y;
  };
  return s;
}

// The continuum bending energy: 1/2 int k^T D k dA by a 12 x 12-point Gauss rule on 8 x 8 cells.
double continuum_bending(const Surface& s, const rs::SheetMaterial& m) {
  double energy = 0;
  for (int i = 0; i < 8; ++i) {
    const ss::GaussRule ru = ss::gauss_legendre(12, i * kW / 8, (i + 1) * kW / 8);
    for (int j = 0; j < 8; ++j) {
      const ss::GaussRule rv = ss::gauss_legendre(12, j * kH / 8, (j + 1) * kH / 8);
      for (int a = 0; a < 12; ++a) {
        for (int b = 0; b < 12; ++b) {
          const rs::Vec15 y = s.derivatives(ss::Vec2(ru.points[a], rv.points[b]));
          energy += ru.weights[a] * rv.weights[b] *
                    rs::kirchhoff_love_density(y, Eigen::Vector3d::Zero(), m.bending_D_Nm(), 0.0, nullptr, nullptr);
        }
      }
    }
  }
  return energy;
}

ss::SplinePatch uniform_patch(int degree, int elements_u, int elements_v, double w = kW, double h = kH) {
  return shell_fixtures::uniform_patch(degree, elements_u, elements_v, w, h);
}

}  // namespace

TEST_CASE("spline shell: bending energies of exact surfaces converge to the plate's at the promised order", "[spline_shell]") {
  const rs::SheetMaterial m = shell_fixtures::composite(3e-4);
  const std::vector<Surface> surfaces = {cylinder(0, 0.1),   cylinder(30, 0.1),           cylinder(45, 0.1),
                                         cylinder(90, 0.1),  cylinder(135, 0.1),          quadric("twist", 0, 4, 0),
                                         quadric("saddle", 5, 0, -5), quadric("dome", 5, 0, 5)};
  for (int degree : {2, 3}) {
    for (const Surface& s : surfaces) {
      const double exact = continuum_bending(s, m);
      std::vector<double> errors;
      double membrane[3] = {0, 0, 0};
      for (int level = 0; level < 3; ++level) {
        const int n = 4 << level;
        const ss::ShellModel model(uniform_patch(degree, n, n * 3 / 4), m);
        const ss::VecX x = model.patch().interpolate(s.position);
        errors.push_back(std::abs(model.bending_energy(x) - exact) / exact);
        membrane[level] = model.membrane_energy(x);
      }
      const double order = std::log2(errors[1] / errors[2]);
      const bool exact_in_space = errors[1] < 1e-12;
      std::printf("degree %d %-22s relative bending-energy error %.2e %.2e %.2e (4, 8, 16 elements), %s %.2f\n", degree,
                  s.name.c_str(), errors[0], errors[1], errors[2],
                  exact_in_space ? "in the space (rounding only), log2 ratio" : "observed order", order);
      INFO("degree " << degree << ", " << s.name << ": errors " << errors[0] << " " << errors[1] << " " << errors[2]);
      // Interpolation puts the curvature within O(h^(p-1)) of the surface's; the energy error is
      // first order in it (or better where it cancels). A surface the space holds exactly (the
      // cubic space's quadrics) leaves only rounding.
      CHECK((errors[2] < errors[1] || exact_in_space));
      CHECK((order > degree - 1 - 0.2 || exact_in_space));
      CHECK(errors[2] < (degree == 2 ? 5e-3 : 2e-4));
      if (s.name.rfind("cylinder", 0) == 0) {
        // Isometric: the interpolant's strain is its O(h^p) error, its membrane energy O(h^2p).
        INFO("membrane energy " << membrane[1] << " then " << membrane[2] << " J");
        CHECK(membrane[2] < membrane[1] / std::pow(2.0, 2 * degree - 0.5));
      }
    }
  }
}

TEST_CASE("spline shell: a cantilever under its own weight converges to Euler-Bernoulli", "[spline_shell]") {
  // A strip L x b with D12 = 0 and nu = 0 bends as a beam of rigidity D b: tip deflection
  // q L^4 / (8 D) per unit width, q = rho g. Stiff enough that the deflection is 0.06 % of L
  // (the large-rotation correction is then 1e-7 of it).
  const double L = 0.2, b = 0.04;
  rs::SheetMaterial m;
  m.density_kg_m2 = 0.3;
  m.membrane_C_N_m = Eigen::Vector3d(1e6, 1e6, 5e5).asDiagonal();
  m.D11_Nm = 50.0, m.D22_Nm = 50.0, m.D12_Nm = 0.0, m.D66_Nm = 20.0;
  const double expected_m = m.density_kg_m2 * rs::kGravity_m_s2 * std::pow(L, 4) / (8.0 * m.D11_Nm);
  for (int degree : {2, 3}) {
    std::vector<double> errors;
    for (int level = 0; level < 3; ++level) {
      ss::ShellModel model(uniform_patch(degree, 2 << level, 2, L, b), m);
      ss::VecX x = model.patch().flat_positions();
      // The clamp: the first two columns of controls hold position and slope at u = 0.
      ss::ShellHolds holds;
      for (int j = 0; j < model.patch().nv(); ++j) {
        for (int i = 0; i < 2; ++i) holds.fixed_controls.push_back(model.patch().control(i, j));
      }
      const ss::ShellSolveReport report = ss::solve_shell(model, holds, x);
      INFO(report.message);
      REQUIRE(report.converged);
      const double tip_m = -0.5 * (model.patch().position(x, ss::Vec2(L, 0)).z() + model.patch().position(x, ss::Vec2(L, b)).z());
      errors.push_back(std::abs(tip_m - expected_m) / expected_m);
      if (degree == 3 && level == 2) {
        // Its lowest mode is the beam's first: omega = 1.8751^2 sqrt(D / (rho L^4)) (the masses
        // lumped on the controls, so within a few per cent); without the clamp it is free: NaN.
        const double omega = std::pow(1.8751, 2) * std::sqrt(m.D11_Nm / (m.density_kg_m2 * std::pow(L, 4)));
        const double lambda = ss::lowest_eigenvalue_1_s2(model, holds, x);
        std::printf("cantilever lowest eigenvalue %.4g 1/s^2, Euler-Bernoulli's first mode %.4g\n", lambda, omega * omega);
        CHECK(lambda == Approx(omega * omega).epsilon(0.05));
        CHECK(std::isnan(ss::lowest_eigenvalue_1_s2(model, ss::ShellHolds{}, x)));
      }
    }
    const double order = std::log2(errors[1] / errors[2]);
    std::printf("cantilever degree %d: tip deflection relative error %.2e %.2e %.2e (2, 4, 8 elements), observed order %.2f; Euler-Bernoulli %.4f mm\n",
                degree, errors[0], errors[1], errors[2], order, 1e3 * expected_m);
    INFO("degree " << degree << ": " << errors[0] << " " << errors[1] << " " << errors[2]);
    if (degree == 2) {
      CHECK(errors[2] < errors[1]);
      CHECK(order > 1.8);
      CHECK(errors[2] < 1e-2);
    } else {
      // Cubic splines hold the beam's quartic deflection at the tip to the large-rotation
      // term (w / L)^2 = 3.5e-9 at every level (Galerkin's nodal exactness for beams).
      CHECK(errors[0] < 1e-8);
      CHECK(errors[2] < 1e-8);
    }
  }
}
