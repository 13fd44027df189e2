#include "sim_hw/calculix/shell_deck.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::calculix {
namespace {

std::pair<double, double> pad_interval(const DeckJaw& jaw, int axis, double length_m) {
  const double c = jaw.centre_m[axis];
  return {std::max(0.0, c - jaw.half_side_m), std::min(length_m, c + jaw.half_side_m)};
}

std::string set_name(const DeckJaw& jaw) { return "JAW_" + jaw.id; }

}  // namespace

std::vector<double> pad_cuts(const std::vector<DeckJaw>& jaws, int axis, double length_m) {
  std::vector<double> cuts;
  for (const DeckJaw& j : jaws) {
    const auto [a, b] = pad_interval(j, axis, length_m);
    cuts.push_back(a);
    cuts.push_back(b);
  }
  return cuts;
}

std::vector<int> pad_nodes(const ShellGrid& grid, const DeckJaw& jaw) {
  const double w = grid.u_lines_m().back(), h = grid.v_lines_m().back(), tol = 1e-9;
  const auto [u0, u1] = pad_interval(jaw, 0, w);
  const auto [v0, v1] = pad_interval(jaw, 1, h);
  std::vector<int> ids;
  for (int id = 1; id <= grid.node_count(); ++id) {
    const Vec2 p = grid.node_uv_m(id);
    if (p.x() >= u0 - tol && p.x() <= u1 + tol && p.y() >= v0 - tol && p.y() <= v1 + tol) ids.push_back(id);
  }
  return ids;
}

std::string shell_deck_text(const ShellDeck& deck, const std::string& heading) {
  const ShellGrid& g = *deck.grid;
  std::string out = fmt::format("*HEADING\n{}\n*NODE, NSET=NALL\n", heading);
  for (int id = 1; id <= g.node_count(); ++id) {
    const Vec2 uv = g.node_uv_m(id);
    const Vec3 x = deck.origin_m + deck.rotation * Vec3(uv.x(), uv.y(), 0.0);
    out += fmt::format("{}, {:.12g}, {:.12g}, {:.12g}\n", id, x.x(), x.y(), x.z());
  }
  out += "*ELEMENT, TYPE=S8R, ELSET=EALL\n";
  for (int e = 0; e < g.element_count(); ++e) {
    const auto n = g.element_nodes(e);
    out += fmt::format("{}, {}, {}, {}, {}, {}, {}, {}, {}\n", e + 1, n[0], n[1], n[2], n[3], n[4], n[5], n[6], n[7]);
  }
  for (const DeckJaw& j : deck.jaws) {
    const std::vector<int> ids = pad_nodes(g, j);
    if (ids.empty()) throw std::invalid_argument(fmt::format("CalculiX deck: jaw {}'s pad holds no node", j.id));
    out += fmt::format("*NSET, NSET={}\n", set_name(j));
    for (std::size_t k = 0; k < ids.size(); ++k) out += fmt::format("{}{}", ids[k], (k % 16 == 15 || k + 1 == ids.size()) ? "\n" : ", ");
  }
  const ShellSection& s = deck.section;
  out += "*MATERIAL, NAME=SHEET\n";
  // One row per decade of the continuation: temperature T holds the modulus 10^T times the material's.
  for (int t = 0; t <= deck.stiffening_decades; ++t) {
    const double f = std::pow(10.0, t);
    if (s.isotropic) {
      if (t == 0) out += "*ELASTIC\n";
      out += fmt::format("{:.12g}, {:.12g}, {}\n", f * s.e1_Pa, s.nu12, t);
    } else {
      // E1, E2, E3, nu12, nu13, nu23, G12, G13 / G23, T: the thickness decoupled, transverse shear as in-plane.
      if (t == 0) out += "*ELASTIC, TYPE=ENGINEERING CONSTANTS\n";
      out += fmt::format("{:.12g}, {:.12g}, {:.12g}, {:.12g}, 0, 0, {:.12g}, {:.12g}\n{:.12g}, {}\n", f * s.e1_Pa,
                         f * s.e2_Pa, f * std::max(s.e1_Pa, s.e2_Pa), s.nu12, f * s.g12_Pa, f * s.g12_Pa, f * s.g12_Pa, t);
    }
  }
  out += fmt::format("*DENSITY\n{:.12g}\n", s.density_kg_m3);
  const Vec3 a = deck.rotation.col(0), b = deck.rotation.col(1);
  out += fmt::format("*ORIENTATION, NAME=SHEET_AXES, SYSTEM=RECTANGULAR\n{:.12g}, {:.12g}, {:.12g}, {:.12g}, {:.12g}, {:.12g}\n",
                     a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
  out += fmt::format("*SHELL SECTION, ELSET=EALL, MATERIAL=SHEET, ORIENTATION=SHEET_AXES\n{:.12g}\n", s.thickness_m);
  out += "*BOUNDARY\n";
  // Translations and rotations: held in translation only, a pad's elements would let the sheet turn
  // about their edge (the cantilever of tests/sim_hw/calculix sags 2 % more than Euler-Bernoulli so).
  for (const DeckJaw& j : deck.jaws) out += fmt::format("{}, 1, 6\n", set_name(j));
  out += fmt::format("*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, {}\n", deck.stiffening_decades);
  const auto step_head = [&](const std::string& title) {
    return fmt::format("** {}\n*STEP, NLGEOM, INC=100000\n*STATIC\n{:.6g}, 1.0, {:.6g}, {:.6g}\n", title,
                       deck.initial_increment, deck.min_increment, deck.max_increment);
  };
  out += step_head(fmt::format("the hang: gravity on the flat sheet {} decades stiffer, the jaws closed on it",
                                deck.stiffening_decades));
  out += fmt::format("*DLOAD\nEALL, GRAV, {:.12g}, 0, 0, -1\n*NODE FILE, OUTPUT=2D\nU\n*END STEP\n", deck.gravity_m_s2);
  if (deck.stiffening_decades > 0) {
    out += step_head("the hang: the stiffness down to the material's");
    out += "*TEMPERATURE\nNALL, 0\n*NODE FILE, OUTPUT=2D\nU\n*END STEP\n";
  }
  for (std::size_t k = 0; k < deck.stage_displacements_m.size(); ++k) {
    const std::vector<Vec3>& d = deck.stage_displacements_m[k];
    if (d.size() != deck.jaws.size()) {
      throw std::invalid_argument(fmt::format("CalculiX deck: stage {} moves {} jaws, the deck has {}", k + 1, d.size(),
                                              deck.jaws.size()));
    }
    out += step_head(fmt::format("stage {}: the jaws at its poses", k + 1));
    out += "*BOUNDARY\n";
    for (std::size_t j = 0; j < d.size(); ++j) {
      for (int c = 0; c < 3; ++c) out += fmt::format("{}, {}, {}, {:.12g}\n", set_name(deck.jaws[j]), c + 1, c + 1, d[j][c]);
    }
    out += "*NODE FILE, OUTPUT=2D\nU\n*END STEP\n";
  }
  return out;
}

}  // namespace sim_hw::calculix
