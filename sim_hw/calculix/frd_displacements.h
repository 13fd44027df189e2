#pragma once
// The nodal displacements in a CalculiX result file (.frd, ASCII), as ccx writes them for
// `*NODE FILE` / `U`: one DISP block per stored increment, headed by its step and increment
// (the "1PSTEP" record) and step time (the "100C" record), then one "-1" record per node (node id,
// then D1 D2 D3). A shell's results are on its own nodes only with `*NODE FILE, OUTPUT=2D` (without,
// ccx writes its expanded bricks' nodes, numbered after the model's).

#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace sim_hw::calculix {

struct FrdDisplacements {
  int step = 0, increment = 0;
  double total_time = 0;  // the analysis time when stored (ccx counts it on from step to step)
  std::unordered_map<int, Eigen::Vector3d> displacement_m;  // node id -> D1 D2 D3
};

// Every DISP block in order. Throws std::runtime_error naming the file and line for a record that
// cannot be read, or a file that cannot be opened.
std::vector<FrdDisplacements> read_frd_displacements(const std::string& path);

// The last block of each step (steps in order).
std::vector<FrdDisplacements> last_of_each_step(const std::vector<FrdDisplacements>& blocks);

}  // namespace sim_hw::calculix
