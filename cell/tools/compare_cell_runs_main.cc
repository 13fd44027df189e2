// compare_cell_runs: do two runs of the cell agree cycle by cycle? Reads two lcm-logger logs of
// cell runs (SHEET_OBSERVED and SHEET_PREDICTED), pairs their cycles by cycle id and prints how
// far the twin's predictions and the tracked sheets of the same cycle are apart, the worst cycle
// and the first one that differs by more than the tolerance. On the fake world's simulation
// clock in lockstep ("clock": "sim") two runs of one config must agree to rounding:
//   compare_cell_runs A.lcmlog B.lcmlog [--tolerance-mm 0.01]
// Exit status: 0 they agree within the tolerance on every common cycle, 1 they do not, 2 a log
// could not be read or has no cycle in common with the other.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <map>

#include "cell/cell_log_cycles.h"

namespace {

double max_vertex_distance(const twin::VecX& a, const twin::VecX& b) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i + 2 < a.size(); i += 3) worst = std::max(worst, (a.segment<3>(i) - b.segment<3>(i)).norm());
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Compare two cell runs cycle by cycle from their lcm-logger logs"};
  std::string a_path, b_path;
  double tolerance_mm = 0.01;
  int vertices = 0;
  app.add_option("log_a", a_path, "lcm-logger log of the first run")->required();
  app.add_option("log_b", b_path, "lcm-logger log of the second run")->required();
  app.add_option("--tolerance-mm", tolerance_mm, "largest vertex distance that counts as the same (mm)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--vertices", vertices, "the twin mesh's vertex count (default: from the logs)");
  CLI11_PARSE(app, argc, argv);
  try {
    const cell::LoggedCycles a = cell::read_logged_cycles(a_path, vertices);
    const cell::LoggedCycles b = cell::read_logged_cycles(b_path, vertices);
    std::map<long long, const twin::diagnosis::SheetCycle*> by_id;
    for (const auto& c : b.cycles) by_id[c.cycle_id] = &c;
    int common = 0;
    double worst_predicted = 0, worst_observed = 0, sum_predicted = 0;
    long long worst_cycle = -1, first_differing = -1;
    for (const auto& ca : a.cycles) {
      const auto it = by_id.find(ca.cycle_id);
      if (it == by_id.end() || it->second->predicted_m.size() != ca.predicted_m.size()) continue;
      ++common;
      const double p = max_vertex_distance(ca.predicted_m, it->second->predicted_m);
      const double o = max_vertex_distance(ca.observed_m, it->second->observed_m);
      sum_predicted += p;
      if (p > worst_predicted) worst_predicted = p, worst_cycle = ca.cycle_id;
      worst_observed = std::max(worst_observed, o);
      if (first_differing < 0 && 1e3 * std::max(p, o) > tolerance_mm) first_differing = ca.cycle_id;
    }
    fmt::print("{}: {} cycles; {}: {} cycles; {} in common\n", a_path, a.cycles.size(), b_path, b.cycles.size(), common);
    if (common == 0) {
      fmt::print(stderr, "compare_cell_runs: no cycle in common (is the twin's vertex count the same? --vertices)\n");
      return 2;
    }
    fmt::print("predictions: largest vertex distance {:.6f} mm (cycle {}), mean over cycles of the largest {:.6f} mm\n",
               1e3 * worst_predicted, worst_cycle, 1e3 * sum_predicted / common);
    fmt::print("tracked sheets: largest vertex distance {:.6f} mm\n", 1e3 * worst_observed);
    if (first_differing >= 0) {
      fmt::print("DIFFER: first cycle beyond {:.3f} mm: {}\n", tolerance_mm, first_differing);
      return 1;
    }
    fmt::print("SAME within {:.3f} mm on every common cycle\n", tolerance_mm);
  } catch (const std::exception& e) {
    fmt::print(stderr, "compare_cell_runs: {}\n", e.what());
    return 2;
  }
  return 0;
}
