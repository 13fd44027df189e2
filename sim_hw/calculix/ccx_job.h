#pragma once
// Running Debian's ccx on a deck and reading the sheet back: the job in its own folder
// (jobname.inp in, jobname.frd and ccx.log out), and material points of the sheet placed by a
// step's displacements through the elements' own shape functions.

#include <string>
#include <vector>

#include "sim_hw/calculix/frd_displacements.h"
#include "sim_hw/calculix/shell_deck.h"

namespace sim_hw::calculix {

struct CcxJob {
  std::string directory, name = "sheet", ccx = "ccx";
  int threads = 1;
};

// Writes the deck's text to directory/name.inp and runs ccx there (its output to ccx.log),
// unless `reuse` and a result newer than an identical deck is there. Returns the last stored
// displacements of each step (a step ccx did not finish ends with a step time below 1).
// Throws std::runtime_error when ccx cannot be started or leaves no result, naming the log.
std::vector<FrdDisplacements> run_ccx(const CcxJob& job, const std::string& deck_text, bool reuse = false);

// Whether a step's last stored increment ended it: the decks' steps each last one unit of
// analysis time, so step k ends at time k.
bool step_completed(const FrdDisplacements& d);

// Where material points uv (m) of the deck's sheet are (m, world) at displacements d: the flat
// placement plus d, interpolated on the element holding each point. Throws std::runtime_error
// for a node d has no value for.
std::vector<Vec3> sheet_points(const ShellDeck& deck, const FrdDisplacements& d, const std::vector<Vec2>& uv_m);

}  // namespace sim_hw::calculix
