#pragma once
// A cell run's sheets from an lcm-logger log: per cycle, the tracked sheet (SHEET_OBSERVED)
// and the twin's prediction (SHEET_PREDICTED) of the same cycle_id, paired, for the
// discrepancy analysis of a running cell (twin/diagnosis/cycle_residuals.h,
// `diagnose_cell_log`).

#include <cstdint>
#include <string>
#include <vector>

#include "twin/diagnosis/cycle_residuals.h"

namespace cell {

struct LoggedCycles {
  std::vector<twin::diagnosis::SheetCycle> cycles;  // paired, in log order; time_s from the log's first event
  std::int64_t observed = 0, predicted = 0;  // sheet messages read
  std::int64_t unpaired = 0;                 // cycles with only one of the two
  std::int64_t other_mesh = 0;               // cycles skipped: vertex count not the mesh's
  std::int64_t undecodable = 0;              // sheet events that did not decode
  std::int64_t runs = 0;                     // cell start-ups seen (cycle ids begin anew)
};

// Reads every SHEET_OBSERVED and SHEET_PREDICTED event; a cycle is kept when both arrived for
// it with `vertex_count` vertices (<= 0: as many as the first paired cycle has). When cycle ids start again (the cell restarted), the
// cycles of the new run get ids offset past the old ones' so that labels stay unique.
// Throws std::runtime_error naming the file when it cannot be read or is not an LCM log.
LoggedCycles read_logged_cycles(const std::string& log_path, int vertex_count);

}  // namespace cell
