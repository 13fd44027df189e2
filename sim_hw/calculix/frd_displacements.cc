#include "sim_hw/calculix/frd_displacements.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::calculix {
namespace {

// A fixed-width field of a record, as a number.
double number(const std::string& line, std::size_t from, std::size_t width, const std::string& where) {
  if (from >= line.size()) throw std::runtime_error(fmt::format("{}: record too short ({} characters)", where, line.size()));
  const std::string field = line.substr(from, width);
  char* end = nullptr;
  const double v = std::strtod(field.c_str(), &end);
  if (end == field.c_str()) throw std::runtime_error(fmt::format("{}: '{}' is not a number", where, field));
  return v;
}

bool starts_with(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

}  // namespace

std::vector<FrdDisplacements> read_frd_displacements(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the CalculiX result file", path));
  std::vector<FrdDisplacements> blocks;
  FrdDisplacements pending;
  bool in_disp = false;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string where = fmt::format("{}:{}", path, n);
    if (starts_with(line, "    1PSTEP")) {
      std::istringstream s(line.substr(10));
      int counter = 0;
      if (!(s >> counter >> pending.increment >> pending.step)) {
        throw std::runtime_error(fmt::format("{}: expected '1PSTEP block increment step'", where));
      }
    } else if (starts_with(line, "  100C")) {
      pending.total_time = number(line, 12, 12, where);
    } else if (starts_with(line, " -4  DISP")) {
      in_disp = true;
      pending.displacement_m.clear();
    } else if (in_disp && starts_with(line, " -1")) {
      const int id = static_cast<int>(number(line, 3, 10, where));
      pending.displacement_m[id] = {number(line, 13, 12, where), number(line, 25, 12, where), number(line, 37, 12, where)};
    } else if (in_disp && starts_with(line, " -3")) {
      in_disp = false;
      blocks.push_back(pending);
    }
  }
  if (in_disp) throw std::runtime_error(fmt::format("{}: the last DISP block is not closed (a run cut short?)", path));
  return blocks;
}

std::vector<FrdDisplacements> last_of_each_step(const std::vector<FrdDisplacements>& blocks) {
  std::vector<FrdDisplacements> out;
  for (const FrdDisplacements& b : blocks) {
    if (!out.empty() && out.back().step == b.step) out.back() = b;
    else out.push_back(b);
  }
  return out;
}

}  // namespace sim_hw::calculix
