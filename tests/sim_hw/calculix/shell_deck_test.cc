// The CalculiX opinion's deck (sim_hw/calculix): the S8R grid through the jaws' pad edges, the
// shell section that keeps the sheet's bending, the deck's sets and steps.

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>

#include "sim_hw/calculix/shell_deck.h"
#include "sim_hw/calculix/shell_grid.h"
#include "sim_hw/calculix/shell_section.h"
#include "twin/model/material.h"

namespace cx = sim_hw::calculix;

namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("the CalculiX grid runs element edges through every pad edge") {
  const std::vector<cx::DeckJaw> jaws{{"A", {0.11, 0.02}, 0.0133}, {"B", {1.15, 0.5}, 0.0133}};
  const cx::ShellGrid g(1.17, 0.975, 0.04, cx::pad_cuts(jaws, 0, 1.17), cx::pad_cuts(jaws, 1, 0.975));
  for (double cut : {0.11 - 0.0133, 0.11 + 0.0133, 1.15 - 0.0133, 1.17}) {
    bool found = false;
    for (double l : g.u_lines_m()) found = found || std::abs(l - cut) < 1e-12;
    CHECK(found);
  }
  for (std::size_t k = 1; k < g.u_lines_m().size(); ++k) {
    CHECK(g.u_lines_m()[k] - g.u_lines_m()[k - 1] <= 0.04 + 1e-12);
    CHECK(g.u_lines_m()[k] > g.u_lines_m()[k - 1]);
  }
  CHECK(g.v_lines_m().front() == 0.0);
  CHECK(g.v_lines_m()[1] == Approx(0.02 - 0.0133));  // pad A's lower edge
  const int eu = static_cast<int>(g.u_lines_m().size()) - 1, ev = static_cast<int>(g.v_lines_m().size()) - 1;
  CHECK(g.element_count() == eu * ev);
  CHECK(g.node_count() == (2 * eu + 1) * (2 * ev + 1) - eu * ev);  // no centre nodes
}

TEST_CASE("S8R elements are anticlockwise and their shape functions interpolate") {
  const cx::ShellGrid g(0.3, 0.2, 0.1, {0.13}, {});
  for (int e = 0; e < g.element_count(); ++e) {
    const auto n = g.element_nodes(e);
    const cx::Vec2 a = g.node_uv_m(n[0]), b = g.node_uv_m(n[1]), c = g.node_uv_m(n[2]), d = g.node_uv_m(n[3]);
    CHECK(b.x() > a.x());
    CHECK(b.y() == a.y());
    CHECK(c.y() > b.y());
    CHECK(d.x() == a.x());
    CHECK((g.node_uv_m(n[4]) - 0.5 * (a + b)).norm() < 1e-12);
    CHECK((g.node_uv_m(n[5]) - 0.5 * (b + c)).norm() < 1e-12);
    CHECK((g.node_uv_m(n[6]) - 0.5 * (c + d)).norm() < 1e-12);
    CHECK((g.node_uv_m(n[7]) - 0.5 * (d + a)).norm() < 1e-12);
  }
  // Kronecker property and partition of unity.
  const double xi[8] = {-1, 1, 1, -1, 0, 1, 0, -1}, eta[8] = {-1, -1, 1, 1, -1, 0, 1, 0};
  for (int k = 0; k < 8; ++k) {
    const auto s = cx::s8_shape(xi[k], eta[k]);
    for (int m = 0; m < 8; ++m) CHECK(s[m] == Approx(k == m ? 1.0 : 0.0).margin(1e-14));
  }
  // A point located on the grid is interpolated back from its element's nodes.
  for (const cx::Vec2& p : {cx::Vec2(0.05, 0.07), cx::Vec2(0.129, 0.199), cx::Vec2(0.3, 0.0), cx::Vec2(0.2, 0.11)}) {
    const cx::ShellGrid::Location loc = g.locate(p);
    const auto s = cx::s8_shape(loc.xi, loc.eta);
    const auto n = g.element_nodes(loc.element);
    cx::Vec2 q = cx::Vec2::Zero();
    double sum = 0;
    for (int k = 0; k < 8; ++k) q += s[k] * g.node_uv_m(n[k]), sum += s[k];
    CHECK(sum == Approx(1.0));
    CHECK((q - p).norm() < 1e-12);
  }
  CHECK_THROWS_WITH(cx::ShellGrid(0.3, 0.2, 0.1, {0.4}, {}), Catch::Contains("cut 0.4 m along u is off the sheet"));
}

TEST_CASE("the shell section keeps the sheet's bending and its tensile stiffness along u") {
  twin::Material m;
  m.surface_density_kg_m2 = 0.3;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 6000;
  m.shear_stiffness_N_m = 2500;
  m.poisson_ratio = 0.3;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 8e-4;
  const cx::ShellSection s = cx::shell_section(m);
  const double t = s.thickness_m, nu = s.nu12;
  CHECK(s.isotropic);
  CHECK(s.e1_Pa * t * t * t / (12 * (1 - nu * nu)) == Approx(8e-4));     // D, N*m
  CHECK(s.e1_Pa * t / (1 - nu * nu) == Approx(m.membrane_stiffness()(0, 0)));  // C11, N/m
  CHECK(s.density_kg_m3 * t == Approx(0.3));
  CHECK(s.membrane_shear_ratio == Approx(6000 / (2 * 1.3) / 2500));  // the isotropic shell's shear
  CHECK(s.text().find("isotropic") != std::string::npos);

  const cx::ShellSection taut = cx::shell_section(m, cx::ShearFrom::kMembrane);  // the membrane's shear instead
  CHECK_FALSE(taut.isotropic);
  CHECK(taut.g12_Pa * taut.thickness_m == Approx(m.membrane_stiffness()(2, 2)));
  CHECK(taut.membrane_shear_ratio == Approx(1.0));
  CHECK(taut.twist_ratio == Approx(2500.0 / (6000 / (2 * 1.3))));
  CHECK(taut.e1_Pa == Approx(s.e1_Pa));

  m.bending_rigidity_v_Nm = 2e-4;  // a weaker warp: orthotropic, every D term still exact
  const cx::ShellSection o = cx::shell_section(m);
  CHECK_FALSE(o.isotropic);
  const double to = o.thickness_m, d = 1 - o.nu12 * o.nu12 * o.e2_Pa / o.e1_Pa;
  CHECK(o.e1_Pa * std::pow(to, 3) / 12 / d == Approx(m.plate_rigidity()(0, 0)));
  CHECK(o.e2_Pa * std::pow(to, 3) / 12 / d == Approx(m.plate_rigidity()(1, 1)));
  CHECK(o.g12_Pa * std::pow(to, 3) / 12 == Approx(m.plate_rigidity()(2, 2)));
  CHECK(o.membrane_v_ratio == Approx(0.25));

  m.effects.clamp_slip_compliance_m_N = 1e-3;
  CHECK_THROWS_WITH(cx::shell_section(m), Catch::Contains("effects.clamp_slip_compliance_m_N"));
}

TEST_CASE("the deck holds each pad's nodes and has a step per stage after the hang") {
  const std::vector<cx::DeckJaw> jaws{{"A", {0.02, 0.02}, 0.0133}, {"B", {0.28, 0.02}, 0.0133}};
  const cx::ShellGrid g(0.3, 0.2, 0.05, cx::pad_cuts(jaws, 0, 0.3), cx::pad_cuts(jaws, 1, 0.2));
  for (const cx::DeckJaw& j : jaws) {
    const std::vector<int> ids = cx::pad_nodes(g, j);
    CHECK(ids.size() == 8);  // one element's corners and mid-sides: the pad is whole elements
    for (int id : ids) CHECK((g.node_uv_m(id) - j.centre_m).lpNorm<Eigen::Infinity>() <= 0.0133 + 1e-9);
  }
  twin::Material m;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 8e-4;
  cx::ShellDeck deck;
  deck.grid = &g;
  deck.section = cx::shell_section(m);
  deck.jaws = jaws;
  deck.origin_m = {0, 0, 1};
  deck.stage_displacements_m = {{{0.01, 0, 0}, {-0.01, 0, 0}}, {{0, 0, 0.1}, {0, 0, 0.1}}};
  const std::string text = cx::shell_deck_text(deck, "test");
  CHECK(count(text, "*STEP, NLGEOM") == 4);  // the hang (gravity, then down the stiffness) and two stages
  CHECK(deck.first_stage_step() == 3);
  CHECK(count(text, "*NSET, NSET=JAW_") == 2);
  CHECK(text.find("*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, 3") != std::string::npos);
  CHECK(text.find("JAW_B, 1, 1, -0.01") != std::string::npos);
  CHECK(text.find("JAW_A, 1, 6\n") != std::string::npos);  // pads held in rotation too
  CHECK(count(text, "*NODE FILE, OUTPUT=2D") == 4);             // results on the shell's own nodes
  CHECK(text.find("JAW_A, 3, 3, 0.1") != std::string::npos);
  CHECK(count(text, "\n" + std::to_string(g.node_count()) + ", ") >= 1);
  deck.stage_displacements_m.push_back({{0, 0, 0}});
  CHECK_THROWS_WITH(cx::shell_deck_text(deck, "test"), Catch::Contains("stage 3 moves 1 jaws, the deck has 2"));
}
