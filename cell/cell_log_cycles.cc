#include "cell/cell_log_cycles.h"

#include <lcm/lcm-cpp.hpp>
#include <map>
#include <optional>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <stdexcept>

#include "drivers/lcm_channels.h"
#include "drivers/lcm_message_checks.h"
#include "drivers/lcm_wire_check.h"

namespace cell {
namespace {

namespace ch = drivers::channels;

twin::VecX positions(const prepreg_lcm::sheet_state_t& m) {
  twin::VecX x(3 * static_cast<Eigen::Index>(m.num_vertices));
  for (int v = 0; v < m.num_vertices; ++v) x.segment<3>(3 * v) = twin::Vec3(m.x_m[v], m.y_m[v], m.z_m[v]);
  return x;
}

struct Pending {
  std::optional<prepreg_lcm::sheet_state_t> observed, predicted;
};

}  // namespace

LoggedCycles read_logged_cycles(const std::string& log_path, int vertex_count) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("LCM log " + log_path + ": cannot open for reading");
  LoggedCycles out;
  std::map<std::int64_t, Pending> pending;  // by cycle id of the current run
  std::int64_t highest = -1;                // highest cycle id of the current run
  std::int64_t offset = 0;                  // added to the current run's ids
  std::optional<std::int64_t> first_utime;
  std::int64_t events = 0;
  const auto finish = [&](std::int64_t id, Pending& p) {
    if (!p.observed || !p.predicted) {
      ++out.unpaired;
      return;
    }
    if (vertex_count <= 0) vertex_count = p.predicted->num_vertices;  // the first paired cycle's mesh
    if (p.observed->num_vertices != vertex_count || p.predicted->num_vertices != vertex_count) {
      ++out.other_mesh;
      return;
    }
    twin::diagnosis::SheetCycle c;
    c.cycle_id = static_cast<long long>(id + offset);
    if (!first_utime) first_utime = p.observed->utime;
    c.time_s = 1e-6 * static_cast<double>(p.observed->utime - *first_utime);
    c.observed_m = positions(*p.observed);
    c.predicted_m = positions(*p.predicted);
    if (p.observed->num_observed_flags == vertex_count) {
      c.seen.assign(p.observed->vertex_observed.begin(), p.observed->vertex_observed.end());
    }
    out.cycles.push_back(std::move(c));
  };
  const auto flush_before = [&](std::int64_t id) {  // cycles older than id are complete
    while (!pending.empty() && pending.begin()->first < id) {
      finish(pending.begin()->first, pending.begin()->second);
      pending.erase(pending.begin());
    }
  };
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    ++events;
    const bool observed = event->channel == ch::kSheetObserved;
    if (!observed && event->channel != ch::kSheetPredicted) continue;
    prepreg_lcm::sheet_state_t m;
    if (!drivers::decode_checked(event->data, static_cast<int>(event->datalen), m).empty() ||
        !drivers::message_problem(m).empty() || m.cycle_id < 0) {
      ++out.undecodable;
      continue;
    }
    ++(observed ? out.observed : out.predicted);
    if (highest >= 0 && m.cycle_id + 1 < highest) {
      // The ids began anew: the cell was started again.
      flush_before(highest + 1);
      offset += highest + 1;
      highest = -1;
      ++out.runs;
    }
    if (out.runs == 0) out.runs = 1;
    highest = std::max(highest, m.cycle_id);
    flush_before(m.cycle_id - 1);  // a cycle two behind the newest is complete
    Pending& p = pending[m.cycle_id];
    (observed ? p.observed : p.predicted) = std::move(m);
  }
  if (events == 0) throw std::runtime_error("LCM log " + log_path + ": no events (empty or not an LCM log)");
  flush_before(highest + 1);
  return out;
}

}  // namespace cell
