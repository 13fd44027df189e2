#pragma once
// Stage 4 of the tracker: non-rigid registration of the predicted mesh p to the sheet's cloud,
// started from the prediction, robust to predictions 10-15 cm off (after a clamp release the
// twin can be that wrong).
//
// Every vertex moves freely in 3D (a normal-only move cannot carry material sideways, and an
// edge-vector term (x_a - x_b) - (p_a - p_b) fights the rotation of edges that large shape
// changes need). Each iteration fixes the matches, normals n_i and edge directions d~ at the
// current positions x~ and minimises over x (local-global, as in projective dynamics):
//   sum_matched |x_i - t_i|^2 + beta_i |x_i - c_i|^2  vertex -> cloud: c_i the closest cloud
//                                                     point within the gate, t_i = x~_i projected
//                                                     on the plane through c_i normal to n_i
//                                                     (point-to-plane); beta small, larger on the
//                                                     mesh border whose position along the
//                                                     surface is seen
// + gamma sum_i |x_i - m_i|^2                         cloud -> surface: m_i the centroid of the
//                                                     cloud points whose nearest vertex is i, so
//                                                     the border follows the seen extent
// + kappa sum_edges |(x_a - x_b) - L_ab d~_ab|^2      the sheet barely stretches: edges keep their
//                                                     rest length L (rest_uv_m, else as predicted)
//                                                     along their current direction, so they may
//                                                     rotate and the sheet may bend freely
// + mu sum_edges |(x_a - x_b) - (p_a - p_b)|^2        small smoothness of the displacement x - p
// + eps sum_i |x_i - p_i|^2                           anchors parts nobody sees to the prediction
// Every term is isotropic in x, so the three coordinates share one n x n matrix (mesh graph
// Laplacian plus a diagonal): one sparse Cholesky, three solves. (A Gauss-Newton step on 3n
// unknowns with the anisotropic point-to-plane and edge-length blocks was measured 12x slower to
// factorise on the 3111-vertex benchmark mesh.) The iteration reaches the same fixed point: on
// the planes, edges at rest length. Every vertex carries the data terms' full weight: one
// without a match (or with fewer cloud points than typical, for that share) is held where it is
// by it, a term that vanishes at the fixed point. So the matrix depends only on the weights and
// the mesh: factorised once per topology, and each iteration only solves. The gate halves from
// initial_gate_m (16 cm, for 10-15 cm offsets) to final_gate_m.
// Limitation: sliding the whole sheet along itself (a prediction shifted sideways by a few cm)
// converges slowly: only the border and the weak point-to-point terms see that offset.

#include <memory>
#include <string>
#include <vector>

#include "tracking/point_index.h"
#include "tracking/surface_mesh.h"

namespace tracking {

struct RegistrationOptions {
  int max_iterations = 6;  // gates 16, 8, 4, 2, 1.5, 1.5 cm
  double initial_gate_m = 0.16;  // matches farther than this are ignored in the first iteration
  double final_gate_m = 0.015;   // the gate halves each iteration down to this
  // Length (m) over which the displacement is smoothed; mu is smoothness_weight *
  // (smoothing_length / mean edge length)^2 so the result does not depend on mesh resolution.
  double smoothing_length_m = 0.04;
  double smoothness_weight = 0.1;  // mu relative to the data weight, at smoothing_length
  double point_weight = 0.1;  // beta: point-to-point share of the vertex -> cloud term
  // beta on the mesh border. 1.0 pulled border vertices sideways onto the seen edge where the
  // cloud merely stops (a camera's view ends): 0.3 keeps the seams smooth (tests).
  double border_point_weight = 0.3;
  double cloud_to_surface_weight = 0.5;  // gamma
  // kappa, scaled like mu. Stiffer (10) converged too slowly within the iterations (end-to-end
  // mean 3.0 mm instead of 2.2 mm).
  double stretch_weight = 2.0;
  bool use_rest_lengths = true;  // false: the prediction's edge lengths are the reference
  // Every k-th cloud point pulls its nearest vertex: 4 costs half of 2 and tracks as well.
  int cloud_stride = 4;
  double prior_weight = 1e-3;          // eps
  // Stop (once the gate is final) when the vertices' RMS move in an iteration is below this.
  // An RMS, not the largest move: the fits never got the largest below it (all iterations
  // ran); as an RMS it ends warm fits after two iterations.
  double converged_step_m = 2e-4;
  double observed_distance_m = 0.012;  // a vertex with a cloud point this close was observed
  // Warm start (sheet_tracker.h): the fit starts from the prediction moved along its normals
  // by the last cycle's correction, so the first gate only has to cover how far the sheet moved
  // differently from the prediction within one cycle, not the prediction's own error. The
  // gates halve from warm_gate_m, for at most warm_max_iterations: on the twin's hanging sheet
  // seen by simulated D415s, three warm iterations a cycle leave the tracked vertices as close
  // to their true positions as six cold ones (3.8-3.9 against 3.8-4.2 mm mean) and the surface
  // closer (1.9 against 2.1-2.2 mm).
  bool warm_start = true;
  double warm_gate_m = 0.03;
  int warm_max_iterations = 3;
  // A warm fit that matched fewer vertices than this share of the last cycle's (the sheet
  // moved farther than the gate) is redone from the prediction with the full gates.
  double warm_min_matched_fraction = 0.9;
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
  int factorisations = 0;    // numeric factorisations this fit needed (0: the last one's reused)
};

class SurfaceRegistration {
 public:
  SurfaceRegistration();
  ~SurfaceRegistration();
  void set_options(const RegistrationOptions& options) { options_ = options; }
  const RegistrationOptions& options() const { return options_; }

  // Fits `prediction` to the points of `cloud`. Never throws; a mesh that fails validate_mesh
  // or an empty cloud returns the prediction with a status. With `start` (one finite position
  // per vertex of the prediction) the iteration starts there with the first gate warm_gate_m
  // and at most warm_max_iterations, instead of at the prediction with initial_gate_m and
  // max_iterations; the prediction still anchors the prior and smoothness terms.
  RegistrationResult fit(const SurfaceMesh& prediction, const PointIndex& cloud,
                         const std::vector<Vec3>* start = nullptr);

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
