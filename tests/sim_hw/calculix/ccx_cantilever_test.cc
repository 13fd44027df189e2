// CalculiX itself on the opinion's deck (needs calculix-ccx; built only when ccx is found): a
// strip clamped by one jaw and hanging level under gravity deflects as Euler-Bernoulli says, after
// the hang's continuation has brought the stiffness back down to the material's, and a stage that
// lifts the jaw lifts the strip with it.

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "sim_hw/calculix/ccx_job.h"
#include "sim_hw/calculix/shell_deck.h"
#include "sim_hw/calculix/shell_grid.h"
#include "sim_hw/calculix/shell_section.h"
#include "twin/model/material.h"

namespace cx = sim_hw::calculix;

TEST_CASE("ccx on the deck: a clamped strip under gravity deflects as Euler-Bernoulli says") {
  const double length = 0.2, width = 0.04, clamped = 0.02, free = length - clamped;
  twin::Material m;
  m.poisson_ratio = 0.0;  // a strip in bending is a beam: no anticlastic term
  m.surface_density_kg_m2 = 0.3;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 0.05;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 1e5;
  m.shear_stiffness_N_m = 5e4;
  const std::vector<cx::DeckJaw> jaws{{"A", {0.0, 0.5 * width}, clamped}};
  const cx::ShellGrid grid(length, width, 0.01, cx::pad_cuts(jaws, 0, length), cx::pad_cuts(jaws, 1, width));
  cx::ShellDeck deck;
  deck.grid = &grid;
  deck.section = cx::shell_section(m);
  deck.jaws = jaws;
  deck.origin_m = {0, 0, 1};
  deck.stage_displacements_m = {{{0.0, 0.0, 0.05}}};  // the jaw lifted 5 cm
  const std::string dir = (std::filesystem::temp_directory_path() / "calculix_cantilever_test").string();
  std::filesystem::remove_all(dir);
  const auto steps = cx::run_ccx({dir, "strip", CCX_EXE, 1}, cx::shell_deck_text(deck, "cantilever test"));
  REQUIRE(steps.size() == 3);
  for (const auto& s : steps) CHECK(cx::step_completed(s));
  const std::vector<cx::Vec2> tip{{length, 0.5 * width}, {length, 0.0}, {length, width}};
  const double q = m.surface_density_kg_m2 * 9.81;                 // N/m^2
  const double expected = q * std::pow(free, 4) / (8 * 0.05);       // m, about 7.7 mm
  const std::vector<cx::Vec3> hung = cx::sheet_points(deck, steps[1], tip);
  for (const cx::Vec3& p : hung) CHECK(1.0 - p.z() == Approx(expected).epsilon(0.005));
  // Gravity on the thousand-times stiffer sheet alone would have left it within a few microns of level.
  const std::vector<cx::Vec3> stiff = cx::sheet_points(deck, steps[0], tip);
  CHECK(1.0 - stiff[0].z() < 0.01 * expected);
  const std::vector<cx::Vec3> lifted = cx::sheet_points(deck, steps[2], tip);
  CHECK(lifted[0].z() - hung[0].z() == Approx(0.05).epsilon(1e-3));
  std::filesystem::remove_all(dir);
}
