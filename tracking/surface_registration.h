#pragma once
// Stage 4 of the tracker: non-rigid registration of the predicted mesh to the sheet's cloud,
// started from the prediction.
//
// Each Gauss-Newton iteration moves every vertex along its current normal n_i by s_i (x_i =
// x~_i + s_i n_i; depth tells where the surface is, not which material point is where, so the
// tangential placement is left to the prediction) and minimises over s
//   sum_i w_i (s_i - n_i . (c_i - x~_i))^2                      point-to-plane, c_i the closest
//                                                               cloud point within a gate
// + lambda sum_edges |(x_a - x_b) - (p_a - p_b)|^2              keeps the predicted shape (p)
// + eps sum_i |x_i - p_i|^2                                     anchors parts nobody sees
// with the matches and normals fixed, which is quadratic in s: one sparse symmetric solve with
// the pattern of the mesh graph (n unknowns, not 3n). The pattern depends only on the topology,
// so the symbolic analysis (ordering, elimination tree) is done once and reused across
// iterations and cycles. The gate shrinks over the iterations as the mesh approaches the cloud.
// The edge term penalises the gradient of the displacement x - p, so parts no camera sees move
// with their seen neighbours and blend smoothly into the prediction.
// Limitation: a prediction off along a direction other than the normal keeps its tangential
// part (which depth cannot observe), so on a slope a border vertex can end up to about
// offset * sin(slope) beyond the edge the cameras saw.

#include <memory>
#include <string>
#include <vector>

#include "tracking/point_index.h"
#include "tracking/surface_mesh.h"

namespace tracking {

struct RegistrationOptions {
  int max_iterations = 4;  // gate 6, 3, 1.5, 1.5 cm; the benchmark tracks as well with 3 as with 6
  double initial_gate_m = 0.06;  // matches farther than this are ignored in the first iteration
  double final_gate_m = 0.015;   // the gate halves each iteration down to this
  // Length (m) over which the displacement is smoothed; the edge weight lambda is
  // (smoothing_length / mean edge length)^2 so the result does not depend on mesh resolution.
  double smoothing_length_m = 0.04;
  double prior_weight = 1e-3;          // eps
  double converged_step_m = 2e-4;      // stop when no vertex moved more than this
  double observed_distance_m = 0.012;  // a vertex with a cloud point this close was observed
};

enum class RegistrationStatus { kOk, kBadMesh, kNoCloud, kSolverFailed };
const char* to_string(RegistrationStatus status);

struct RegistrationResult {
  RegistrationStatus status = RegistrationStatus::kOk;
  std::string message;
  std::vector<Vec3> vertices_m;             // tracked surface (prediction when not ok)
  std::vector<std::uint8_t> observed;       // 1 when a cloud point lies within observed_distance
  std::vector<double> distance_to_cloud_m;  // nearest cloud point (m); NaN when beyond the gate
  int iterations = 0;
  int matched_vertices = 0;  // in the last iteration
};

class SurfaceRegistration {
 public:
  SurfaceRegistration();
  ~SurfaceRegistration();
  void set_options(const RegistrationOptions& options) { options_ = options; }
  const RegistrationOptions& options() const { return options_; }

  // Fits `prediction` to the points of `cloud`. Never throws; a mesh that fails validate_mesh
  // or an empty cloud returns the prediction with a status.
  RegistrationResult fit(const SurfaceMesh& prediction, const PointIndex& cloud);

  // How many times the sparsity pattern was analysed (once per topology); lets tests check reuse.
  int symbolic_analyses() const { return symbolic_analyses_; }

 private:
  void prepare_topology(const SurfaceMesh& prediction);

  RegistrationOptions options_;
  struct Solver;
  std::unique_ptr<Solver> solver_;
  int symbolic_analyses_ = 0;
};

}  // namespace tracking
