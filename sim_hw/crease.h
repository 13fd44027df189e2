#pragma once
// A crease: physics no candidate effect of the twin represents (issue 6's "outside the library"
// blind set). The ply was folded sharply along a straight line once, so the hinges the line cuts
// rest at an angle instead of flat. A rest curvature spreads a bend evenly over the sheet; a
// crease puts it all on one line, so fitting the twin's effects cannot explain it.
//
// Applied to the scanner lab's sheet only (ScannerLabConfig::creases): on a twin reference by
// apply_crease below, after its material is set (ShellModel::set_material recomputes rest
// angles from the material); on the independent sheet as a band of rest curvature
// (real_sheet/sheet_material.h), that model's own form of the same fold.

#include "twin/model/shell_model.h"
#include "twin/base/types.h"

namespace sim_hw {

struct Crease {
  twin::Vec2 point_m = twin::Vec2::Zero();  // a point of the crease line, material coordinates
  double direction_rad = 0.0;               // the line's direction, from the u axis
  double angle_rad = 0.0;                   // fold across the line (signed: valley or mountain)
};

// Adds the crease to the rest angles of the hinges whose two triangles' centroids lie on either
// side of the line, each weighted by how squarely its edge faces the line's normal (a zig-zag
// of edges shares the fold). Returns how many hinges it changed.
int apply_crease(twin::ShellModel& model, const Crease& crease);

}  // namespace sim_hw
