#pragma once
// The residual field of a running cell (issue 6, step 1, "per cycle for cell logs"): each
// cycle's tracked sheet (what the cameras saw, on the twin's mesh) minus the twin's prediction
// for that cycle, one sample per observed vertex. A cycle becomes one stage of the field, so
// the same analysis as for scanner trials (residual_analysis.h) gives chi-square per cycle and
// per region and the structure over material direction, clamp distance, curvature, load and
// the time since a clamp moved. Reading the cell's LCM logs into SheetCycle is the cell's job
// (cell/cell_log_cycles.h): nothing here knows LCM.

#include <string>
#include <vector>

#include "twin/model/clamp.h"
#include "twin/diagnosis/residual_field.h"
#include "twin/mesh/sheet_mesh.h"

namespace twin::diagnosis {

struct SheetCycle {
  long long cycle_id = 0;
  double time_s = 0.0;       // when the observed frames were captured (s, any fixed epoch)
  VecX observed_m;           // 3 x vertices, the tracked sheet (m, cell frame)
  std::vector<bool> seen;    // per vertex: observed this cycle (empty: every vertex)
  VecX predicted_m;          // 3 x vertices, the twin's prediction for the same cycle
};

// A grasp point that moves more than this between two cycles counts as a clamp move (m): the
// arms hold a grasp to well under a millimetre, and the twin's clamp follows the measured pose.
inline constexpr double kClampMoveM = 1e-3;

// Appends one FieldTrial named `name` with one stage per cycle (label "<name>/<cycle id>"):
// samples at the cycle's observed vertices (marker = vertex index, uv = the vertex's rest
// position). The clamps are the grasps' material points on `mesh`; their positions in a cycle
// are read off the prediction at those points (the twin holds them where the arms are), and
// every grasp counts as engaged. A stage's age is the time since a grasp point last moved by
// more than kClampMoveM from one cycle to the next (NaN until a move has been seen); its load
// is the highest grasp point above the grasp points' mean height in the first cycle.
// `selected`: the indices of the cycles that become stages, ascending (empty: all); the ages
// still follow every cycle, so a long log can be analysed on a sample of its cycles.
// Throws std::invalid_argument naming the cycle when its arrays do not match the mesh or hold
// non-finite values where a vertex is observed.
void add_cycle_residuals(ResidualField& field, const SheetMesh& mesh, const std::vector<ClampSpec>& clamps,
                         const std::vector<SheetCycle>& cycles, const std::string& name,
                         const std::vector<std::size_t>& selected = {});

// At most `count` indices of `cycles` cycles, evenly spread, first and last included.
std::vector<std::size_t> spread_cycles(std::size_t cycles, std::size_t count);

}  // namespace twin::diagnosis
