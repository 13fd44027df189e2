#include "sim_hw/calculix/ccx_job.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::calculix {

namespace fs = std::filesystem;

std::vector<FrdDisplacements> run_ccx(const CcxJob& job, const std::string& deck_text, bool reuse) {
  const fs::path dir(job.directory), inp = dir / (job.name + ".inp"), frd = dir / (job.name + ".frd"),
      log = dir / "ccx.log";
  fs::create_directories(dir);
  bool same = false;
  if (fs::exists(inp)) {
    std::ifstream old(inp);
    std::stringstream s;
    s << old.rdbuf();
    same = s.str() == deck_text;
  }
  if (!same) {
    std::ofstream(inp) << deck_text;
    if (fs::exists(frd)) fs::remove(frd);
  }
  if (!(reuse && same && fs::exists(frd) && fs::last_write_time(frd) > fs::last_write_time(inp))) {
    // ccx returns non-zero when a step fails; what it finished is still in the result file.
    const std::string cmd = fmt::format("cd '{}' && OMP_NUM_THREADS={} CCX_NPROC_EQUATION_SOLVER={} '{}' -i '{}' > ccx.log 2>&1",
                                        dir.string(), job.threads, job.threads, job.ccx, job.name);
    const int rc = std::system(cmd.c_str());
    if (rc == -1 || (WIFEXITED(rc) && WEXITSTATUS(rc) == 127)) {
      throw std::runtime_error(fmt::format("cannot run '{}' (calculix-ccx installed?); see {}", job.ccx, log.string()));
    }
  }
  if (!fs::exists(frd)) throw std::runtime_error(fmt::format("ccx left no result file; see {}", log.string()));
  return last_of_each_step(read_frd_displacements(frd.string()));
}

bool step_completed(const FrdDisplacements& d) { return std::abs(d.total_time - d.step) < 1e-6; }

std::vector<Vec3> sheet_points(const ShellDeck& deck, const FrdDisplacements& d, const std::vector<Vec2>& uv_m) {
  const ShellGrid& g = *deck.grid;
  std::vector<Vec3> out;
  out.reserve(uv_m.size());
  for (const Vec2& uv : uv_m) {
    const ShellGrid::Location loc = g.locate(uv);
    const auto n = s8_shape(loc.xi, loc.eta);
    const auto ids = g.element_nodes(loc.element);
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < 8; ++a) {
      const auto it = d.displacement_m.find(ids[a]);
      if (it == d.displacement_m.end()) {
        throw std::runtime_error(fmt::format("ccx result of step {}: node {} has no displacement", d.step, ids[a]));
      }
      const Vec2 p = g.node_uv_m(ids[a]);
      x += n[a] * (deck.origin_m + deck.rotation * Vec3(p.x(), p.y(), 0.0) + it->second);
    }
    out.push_back(x);
  }
  return out;
}

}  // namespace sim_hw::calculix
