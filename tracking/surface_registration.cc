// Local-global 3D registration: point-to-plane, cloud-to-surface, rest edge lengths (stage 4).
#include "tracking/surface_registration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/CholmodSupport>

namespace tracking {

namespace {

// Reference length of each edge: from the rest (material) coordinates when the mesh has them,
// else as predicted.
std::vector<double> reference_lengths(const SurfaceMesh& mesh,
                                      const std::vector<std::pair<int, int>>& edges,
                                      bool use_rest) {
  std::vector<double> length(edges.size());
  const bool rest = use_rest && !mesh.rest_uv_m.empty();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = edges[e];
    length[e] = rest ? (mesh.rest_uv_m[a] - mesh.rest_uv_m[b]).norm()
                     : (mesh.vertices_m[a] - mesh.vertices_m[b]).norm();
  }
  return length;
}

}  // namespace

const char* to_string(RegistrationStatus status) {
  switch (status) {
    case RegistrationStatus::kOk:
      return "ok";
    case RegistrationStatus::kBadMesh:
      return "bad mesh";
    case RegistrationStatus::kNoCloud:
      return "no cloud";
    case RegistrationStatus::kSolverFailed:
      return "solver failed";
  }
  return "unknown";
}

struct SurfaceRegistration::Solver {
  std::vector<Eigen::Vector3i> triangles;  // topology the pattern was built for
  int vertices = 0;
  std::vector<std::pair<int, int>> edges;
  std::vector<int> diagonal;  // index into the value array of entry (i, i)
  // Per edge, the value-array indices of (a, b) and (b, a).
  std::vector<std::pair<int, int>> off_diagonal;
  std::vector<std::uint8_t> border;  // 1 for a vertex on an edge of only one triangle
  Eigen::SparseMatrix<double> system;
  // CHOLMOD (its own fill-reducing ordering) measured ~25% faster than Eigen's SimplicialLDLT
  // on the 3111-vertex benchmark mesh (scalar system, n x n). Simplicial LDL' (set in
  // analyze): on the fake cell's scene the matched set changes and the system is refactorised
  // about 3 times a cycle; there its supernodal factorisation (Debian's CHOLMOD runs fixed
  // 4-thread OpenMP loops inside it, which churn on 2 cores) took 3.4 ms and its 3-column
  // solve 0.34 ms per iteration, the simplicial one 1.6 ms and 0.13 ms (registration 24.4 ->
  // 17.5 ms a cycle, `cell_benchmark --phase still`).
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
  bool factorised = false;
  std::array<double, 6> weights{};  // the weights the factorisation was made with
};

SurfaceRegistration::SurfaceRegistration() : solver_(std::make_unique<Solver>()) {}
SurfaceRegistration::~SurfaceRegistration() = default;

void SurfaceRegistration::prepare_topology(const SurfaceMesh& prediction) {
  Solver& s = *solver_;
  const int n = static_cast<int>(prediction.vertices_m.size());
  if (n == s.vertices && prediction.triangles == s.triangles) return;
  s.triangles = prediction.triangles;
  s.vertices = n;
  s.edges = unique_edges(prediction.triangles);
  {
    std::vector<std::pair<int, int>> all;  // every triangle's edges, an inner edge twice
    all.reserve(3 * prediction.triangles.size());
    for (const Eigen::Vector3i& t : prediction.triangles) {
      for (int k = 0; k < 3; ++k) {
        all.emplace_back(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
      }
    }
    std::sort(all.begin(), all.end());
    s.border.assign(n, 0);
    for (std::size_t k = 0; k < all.size(); ++k) {
      const bool once =
          (k == 0 || all[k] != all[k - 1]) && (k + 1 == all.size() || all[k] != all[k + 1]);
      if (once) s.border[all[k].first] = s.border[all[k].second] = 1;
    }
  }
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(n + 2 * s.edges.size());
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, 1.0);
  for (const auto& [a, b] : s.edges) {
    entries.emplace_back(a, b, 0.0);
    entries.emplace_back(b, a, 0.0);
  }
  s.system.resize(n, n);
  s.system.setFromTriplets(entries.begin(), entries.end());
  s.system.makeCompressed();
  const auto entry = [&](int row, int col) {
    const int* inner = s.system.innerIndexPtr();
    const int* begin = inner + s.system.outerIndexPtr()[col];
    const int* end = inner + s.system.outerIndexPtr()[col + 1];
    return static_cast<int>(std::lower_bound(begin, end, row) - inner);
  };
  s.diagonal.resize(n);
  for (int i = 0; i < n; ++i) s.diagonal[i] = entry(i, i);
  s.off_diagonal.clear();
  for (const auto& [a, b] : s.edges) s.off_diagonal.emplace_back(entry(a, b), entry(b, a));
  s.factor.setMode(Eigen::CholmodLDLt);
  s.factor.analyzePattern(s.system);
  s.factorised = false;
  ++symbolic_analyses_;
}

RegistrationResult SurfaceRegistration::fit(const SurfaceMesh& prediction,
                                            const PointIndex& cloud,
                                            const std::vector<Vec3>* start) {
  RegistrationResult result;
  result.vertices_m = prediction.vertices_m;
  const int n = static_cast<int>(prediction.vertices_m.size());
  result.observed.assign(n, 0);
  result.distance_to_cloud_m.assign(n, std::numeric_limits<double>::quiet_NaN());
  if (std::string why = validate_mesh(prediction); !why.empty()) {
    result.status = RegistrationStatus::kBadMesh;
    result.message = why;
    return result;
  }
  if (cloud.size() == 0) {
    result.status = RegistrationStatus::kNoCloud;
    result.message = "no sheet points to register to";
    return result;
  }
  const bool warm = start && start->size() == prediction.vertices_m.size() &&
                    std::all_of(start->begin(), start->end(), [](const Vec3& v) { return v.allFinite(); });
  prepare_topology(prediction);
  Solver& s = *solver_;
  const std::vector<Vec3>& p = prediction.vertices_m;
  const RegistrationOptions& o = options_;

  const std::vector<double> rest = reference_lengths(prediction, s.edges, o.use_rest_lengths);
  double mean_edge = 0.0;
  for (const double l : rest) mean_edge += l;
  mean_edge /= std::max<std::size_t>(rest.size(), 1);
  const double scale = std::pow(o.smoothing_length_m / std::max(mean_edge, 1e-6), 2);
  const double mu = o.smoothness_weight * scale;
  const double kappa = o.stretch_weight * scale;
  const double eps = o.prior_weight;
  const double gamma = o.cloud_to_surface_weight;
  const auto beta = [&](int i) { return s.border[i] ? o.border_point_weight : o.point_weight; };

  // Every cloud_stride-th cloud point pulls its nearest vertex (cloud -> surface term).
  std::vector<Eigen::Vector3f> cloud_sample;
  const int stride = std::max(o.cloud_stride, 1);
  cloud_sample.reserve(cloud.size() / stride + 1);
  for (std::size_t k = 0; k < cloud.size(); k += stride) {
    cloud_sample.push_back(cloud.point(static_cast<int>(k)));
  }

  std::vector<Vec3>& x = result.vertices_m;
  if (warm) x = *start;
  std::vector<int> match(n, -1), owner;
  std::vector<float> match_d2, owner_d2;
  std::vector<Eigen::Vector3f> query(n);
  std::vector<Vec3> pulled(n);
  std::vector<int> pulls(n);
  Eigen::MatrixX3d rhs(n, 3);
  PointIndex vertex_index;
  double gate = warm ? std::min(o.warm_gate_m, o.initial_gate_m) : o.initial_gate_m;
  const int max_iterations = warm ? o.warm_max_iterations : o.max_iterations;
  for (int it = 0; it < max_iterations; ++it) {
    const std::vector<Vec3> normal = vertex_normals(x, prediction.triangles);
    for (int i = 0; i < n; ++i) query[i] = x[i].cast<float>();
    cloud.nearest(query, static_cast<float>(gate), match, match_d2);
    vertex_index.build(query, 0);
    vertex_index.nearest(cloud_sample, static_cast<float>(gate), owner, owner_d2);
    std::fill(pulled.begin(), pulled.end(), Vec3::Zero());
    std::fill(pulls.begin(), pulls.end(), 0);
    int pulled_vertices = 0, pulling_points = 0;
    for (std::size_t k = 0; k < cloud_sample.size(); ++k) {
      if (owner[k] < 0) continue;
      pulled_vertices += pulls[owner[k]]++ == 0;
      ++pulling_points;
      pulled[owner[k]] += cloud_sample[k].cast<double>();
    }
    // A vertex with fewer points than half the typical count (a border vertex half off the
    // seen extent, a stray point) pulls with a proportionally smaller share.
    const double typical = 0.5 * pulling_points / std::max(pulled_vertices, 1);

    // Every vertex carries the data terms' full weight. Where a term has no data (no cloud
    // point within the gate, fewer pulling points than typical) that share holds the vertex
    // where it is instead: a term that vanishes at the fixed point, so the fixed points are
    // those of the fit with the term left out, and the matrix does not depend on which vertices
    // are matched. (A matrix that followed the matched set was refactorised 2-3 times a fit on
    // the fake cell's scene, where vertices at the edge of the seen sheet change sets every
    // cycle: 4 of a fit's 13 ms.)
    int matched = 0;
    for (int i = 0; i < n; ++i) {
      Vec3 b = eps * p[i];
      if (match[i] >= 0) {
        ++matched;
        const Vec3 c = cloud.point(match[i]).cast<double>();
        b += x[i] - normal[i] * normal[i].dot(x[i] - c) + beta(i) * c;
      } else {
        b += (1.0 + beta(i)) * x[i];
      }
      const double share = pulls[i] > 0 ? std::min(1.0, pulls[i] / typical) : 0.0;
      b += gamma * (1.0 - share) * x[i];
      if (share > 0.0) b += gamma * share * pulled[i] / pulls[i];
      rhs.row(i) = b.transpose();
    }
    // The matrix depends only on the weights and the mesh: factorised once per topology.
    const std::array<double, 6> weights{mu, kappa, eps, gamma, o.point_weight,
                                        o.border_point_weight};
    if (!s.factorised || weights != s.weights) {
      double* value = s.system.valuePtr();
      for (int i = 0; i < n; ++i) value[s.diagonal[i]] = eps + 1.0 + beta(i) + gamma;
      for (std::size_t e = 0; e < s.edges.size(); ++e) {
        const auto [a, b] = s.edges[e];
        value[s.diagonal[a]] += kappa + mu;
        value[s.diagonal[b]] += kappa + mu;
        value[s.off_diagonal[e].first] = value[s.off_diagonal[e].second] = -(kappa + mu);
      }
      s.factor.factorize(s.system);
      s.factorised = s.factor.info() == Eigen::Success;
      s.weights = weights;
      ++result.factorisations;
    }
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
      const auto [a, bb] = s.edges[e];
      Vec3 d = x[a] - x[bb];
      if (d.norm() < 1e-9) d = p[a] - p[bb];
      const Vec3 target = kappa * rest[e] * d.normalized() + mu * (p[a] - p[bb]);
      rhs.row(a) += target.transpose();
      rhs.row(bb) -= target.transpose();
    }
    result.matched_vertices = matched;
    Eigen::MatrixX3d solution;
    if (s.factorised) solution = s.factor.solve(rhs);
    if (!s.factorised || s.factor.info() != Eigen::Success || !solution.allFinite()) {
      result.status = RegistrationStatus::kSolverFailed;
      result.message = fmt::format("sparse solve failed in iteration {}", it + 1);
      result.vertices_m = prediction.vertices_m;
      return result;
    }
    // Convergence by the RMS vertex move. The largest single move is no test: on the tracker
    // benchmark's scene it stayed at 0.4-0.7 mm an iteration, at every iteration, while the RMS
    // move fell to 0.1-0.2 mm, so it never ended a fit early.
    double squared_steps = 0.0;
    for (int i = 0; i < n; ++i) {
      const Vec3 next = solution.row(i).transpose();
      squared_steps += (next - x[i]).squaredNorm();
      x[i] = next;
    }
    const double rms_step = std::sqrt(squared_steps / n);
    result.iterations = it + 1;
    const bool gate_final = gate <= o.final_gate_m;
    gate = std::max(0.5 * gate, o.final_gate_m);
    if (gate_final && rms_step < o.converged_step_m) break;
  }

  for (int i = 0; i < n; ++i) query[i] = x[i].cast<float>();
  cloud.nearest(query, static_cast<float>(o.final_gate_m), match, match_d2);
  for (int i = 0; i < n; ++i) {
    if (match[i] >= 0) {
      result.distance_to_cloud_m[i] = std::sqrt(static_cast<double>(match_d2[i]));
      result.observed[i] = result.distance_to_cloud_m[i] <= o.observed_distance_m;
    }
  }
  return result;
}

}  // namespace tracking
