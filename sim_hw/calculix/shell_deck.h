#pragma once
// A CalculiX input deck (.inp) of the scanner lab's protocol on the S8R grid (shell_grid.h): the
// sheet lies flat and level at the placement, each jaw holds the whole elements of its square pad
// (every node in the pad fixed in translation and rotation, so the pad moves rigidly and clamps
// the sheet at its edges), gravity comes on and the sheet hangs (static steps with NLGEOM), and
// each further step moves the jaws to one stage's poses (a pad translates with its clamp: the
// jaws stay level, in the placement's frame). Static steps follow taut stages only: a jaw that
// opens lets the sheet fall, and jaws that come closer than the material between them let it
// slacken and snap into folds, a limit point of the static path where ccx's increments shrink
// below any minimum (docs/reference_sheet.md, "CalculiX's opinion").
// The hang is a continuation, not the lab's overdamped fall: a flat sheet under gravity has only
// its bending to resist (Newton's first iterate from flat drops a 1 m composite sheet hundreds of
// metres, and ccx cuts its increments below any minimum), so gravity comes on with the stiffness
// `stiffening_decades` decades higher (a temperature-dependent modulus, ccx's way to vary a
// material within an analysis; no thermal strain) and the stiffness then comes down a decade per
// unit of temperature to the material's. Equilibria on the way are the same sheet's with a stiffer
// material, so the path stays on the hanging branch the stiff sheet takes.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim_hw/calculix/shell_grid.h"
#include "sim_hw/calculix/shell_section.h"

namespace sim_hw::calculix {

using Vec3 = Eigen::Vector3d;

struct DeckJaw {
  std::string id;
  Vec2 centre_m = Vec2::Zero();  // material point
  double half_side_m = 0;        // the pad, clipped to the sheet
};

struct ShellDeck {
  const ShellGrid* grid = nullptr;
  ShellSection section;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // flat placement: world = origin + R (u, v, 0)
  Vec3 origin_m = Vec3::Zero();
  double gravity_m_s2 = 9.81;  // along -z
  std::vector<DeckJaw> jaws;
  // Per stage, per jaw: the displacement (m, world) of its pad from the flat placement.
  std::vector<std::vector<Vec3>> stage_displacements_m;
  // Static increments: the first, the largest and the smallest fraction of a step (every step lasts
  // one unit of analysis time).
  // A stage whose increments fall below min_increment is not reached (a slack stage's snap, above).
  double initial_increment = 0.02, max_increment = 0.25, min_increment = 1e-5;
  int stiffening_decades = 3;  // the hang starts this many decades stiffer (0: gravity on the material)

  // The step (1-based) that reaches stage 1; stage k is this + k - 1.
  int first_stage_step() const { return stiffening_decades > 0 ? 3 : 2; }
};

// The pad's cut lines along u (axis 0) or v (axis 1), for ShellGrid.
std::vector<double> pad_cuts(const std::vector<DeckJaw>& jaws, int axis, double length_m);

// The node ids inside jaw's pad (its closed square, clipped to the sheet).
std::vector<int> pad_nodes(const ShellGrid& grid, const DeckJaw& jaw);

// The deck's text: the hang, then one step per stage (first_stage_step). Throws
// std::invalid_argument for a stage whose displacement count differs from the jaws', or a pad
// that holds no node.
std::string shell_deck_text(const ShellDeck& deck, const std::string& heading);

}  // namespace sim_hw::calculix
