#include "cell/learning/branch_following.h"

#include <fmt/format.h>

#include <limits>
#include <stdexcept>

#include "twin/mesh/material_point.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/scan_tether.h"

namespace cell::learning {
namespace {

double mean_distance_m(const twin::VecX& x, const std::vector<twin::Vec3>& observed_m) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < observed_m.size(); ++i) {
    if (!observed_m[i].allFinite()) continue;
    sum += (x.segment<3>(3 * static_cast<Eigen::Index>(i)) - observed_m[i]).norm();
    ++count;
  }
  return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

BranchCandidate equilibrium_near_observation(const twin::SheetMesh& mesh, const twin::Material& material,
                                             const std::vector<twin::ClampSpec>& clamps,
                                             const std::vector<twin::ClampPose>& poses, const twin::VecX& current,
                                             const std::vector<twin::Vec3>& observed_m) {
  const int n = mesh.vertex_count();
  if (current.size() != 3 * n || static_cast<int>(observed_m.size()) != n || clamps.size() != poses.size()) {
    throw std::invalid_argument(fmt::format("branch following: state of {} values, {} observed vertices and {} poses "
                                            "for a mesh of {} vertices and {} clamps",
                                            current.size(), observed_m.size(), poses.size(), n, clamps.size()));
  }
  BranchCandidate c;
  c.before_m = mean_distance_m(current, observed_m);
  try {
    twin::ShellModel model(mesh, material);
    const twin::ClampSet clamp_set(model.mesh(), clamps);
    model.set_clamps_of_material_effects(clamp_set);  // as the cell's twin holds them (cell_twin.cc)
    const twin::MaterialPointMap vertices(model.mesh(), model.mesh().rest_uv);
    twin::VecX x = current;
    for (int i = 0; i < n; ++i) {
      if (observed_m[i].allFinite()) x.segment<3>(3 * i) = observed_m[i];
    }
    const twin::SolveReport r = twin::equilibrium_from_scan(model, clamp_set, poses, vertices, observed_m, x);
    if (!r.usable() || !x.allFinite()) {
      c.problem = "no equilibrium from the observed shape: " + r.brief();
      return c;
    }
    c.after_m = mean_distance_m(x, observed_m);
    c.x = std::move(x);
  } catch (const std::exception& e) {  // e.g. out of memory: the twin keeps its state
    c.problem = std::string("threw: ") + e.what();
  }
  return c;
}

}  // namespace cell::learning
