// Gauss-Newton point-to-plane registration with an edge regulariser (stage 4).
#include "tracking/surface_registration.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/SparseCholesky>
#include <fmt/format.h>

namespace tracking {

const char* to_string(RegistrationStatus status) {
  switch (status) {
    case RegistrationStatus::kOk: return "ok";
    case RegistrationStatus::kBadMesh: return "bad mesh";
    case RegistrationStatus::kNoCloud: return "no cloud";
    case RegistrationStatus::kSolverFailed: return "solver failed";
  }
  return "unknown";
}

struct SurfaceRegistration::Solver {
  std::vector<Eigen::Vector3i> triangles;  // topology the pattern was built for
  int vertices = 0;
  std::vector<std::pair<int, int>> edges;
  // Graph Laplacian (x) I3, with explicit zeros filling each vertex's 3x3 diagonal block so the
  // data blocks can be added in place without changing the pattern.
  Eigen::SparseMatrix<double> laplacian;
  std::vector<int> diag_entry;  // 9 per vertex: index into the value array of entry (3i+a, 3i+b)
  Eigen::SparseMatrix<double> system;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
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
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(9 * n + 6 * s.edges.size());
  std::vector<int> degree(n, 0);
  for (const auto& [a, b] : s.edges) {
    ++degree[a];
    ++degree[b];
    for (int k = 0; k < 3; ++k) {
      entries.emplace_back(3 * a + k, 3 * b + k, -1.0);
      entries.emplace_back(3 * b + k, 3 * a + k, -1.0);
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) entries.emplace_back(3 * i + a, 3 * i + b, a == b ? degree[i] : 0.0);
    }
  }
  s.laplacian.resize(3 * n, 3 * n);
  s.laplacian.setFromTriplets(entries.begin(), entries.end());
  s.laplacian.makeCompressed();
  s.diag_entry.assign(9 * n, -1);
  const int* outer = s.laplacian.outerIndexPtr();
  const int* inner = s.laplacian.innerIndexPtr();
  for (int col = 0; col < 3 * n; ++col) {
    const int i = col / 3, b = col % 3;
    for (int k = outer[col]; k < outer[col + 1]; ++k) {
      const int row = inner[k];
      if (row / 3 == i) s.diag_entry[9 * i + 3 * (row % 3) + b] = k;
    }
  }
  s.system = s.laplacian;
  s.ldlt.analyzePattern(s.system);
  ++symbolic_analyses_;
}

RegistrationResult SurfaceRegistration::fit(const SurfaceMesh& prediction, const PointIndex& cloud) {
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
  prepare_topology(prediction);
  Solver& s = *solver_;

  double mean_edge = 0.0;
  for (const auto& [a, b] : s.edges) {
    mean_edge += (prediction.vertices_m[a] - prediction.vertices_m[b]).norm();
  }
  mean_edge /= std::max<std::size_t>(s.edges.size(), 1);
  const double lambda = std::pow(options_.smoothing_length_m / std::max(mean_edge, 1e-6), 2);
  const double mu = options_.tangential_weight, eps = options_.prior_weight;

  Eigen::VectorXd p(3 * n);
  for (int i = 0; i < n; ++i) p.segment<3>(3 * i) = prediction.vertices_m[i];
  // The regulariser and prior alone: lambda L + eps I, and their right-hand side (the
  // prediction's own edge vectors, and the prediction itself).
  Eigen::SparseMatrix<double> base = s.laplacian * lambda;
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) base.valuePtr()[s.diag_entry[9 * i + 4 * a]] += eps;
  }
  const Eigen::VectorXd base_rhs = base * p;

  std::vector<Vec3>& x = result.vertices_m;
  std::vector<int> match(n, -1);
  double gate = options_.initial_gate_m;
  for (int it = 0; it < options_.max_iterations; ++it) {
    const std::vector<Vec3> normals = vertex_normals(x, prediction.triangles);
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; ++i) {
      match[i] = cloud.nearest(x[i].cast<float>(), static_cast<float>(gate), nullptr);
    }
    std::copy(base.valuePtr(), base.valuePtr() + base.nonZeros(), s.system.valuePtr());
    Eigen::VectorXd rhs = base_rhs;
    int matched = 0;
    for (int i = 0; i < n; ++i) {
      if (match[i] < 0) continue;
      ++matched;
      const Vec3 c = cloud.point(match[i]).cast<double>();
      const Eigen::Matrix3d block = normals[i] * normals[i].transpose() + mu * Eigen::Matrix3d::Identity();
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) s.system.valuePtr()[s.diag_entry[9 * i + 3 * a + b]] += block(a, b);
      }
      rhs.segment<3>(3 * i) += block * c;
    }
    result.matched_vertices = matched;
    s.ldlt.factorize(s.system);
    if (s.ldlt.info() != Eigen::Success) {
      result.status = RegistrationStatus::kSolverFailed;
      result.message = fmt::format("sparse factorisation failed in iteration {}", it + 1);
      result.vertices_m = prediction.vertices_m;
      return result;
    }
    const Eigen::VectorXd solution = s.ldlt.solve(rhs);
    if (!solution.allFinite()) {
      result.status = RegistrationStatus::kSolverFailed;
      result.message = fmt::format("non-finite solution in iteration {}", it + 1);
      result.vertices_m = prediction.vertices_m;
      return result;
    }
    double step = 0.0;
    for (int i = 0; i < n; ++i) {
      const Vec3 next = solution.segment<3>(3 * i);
      step = std::max(step, (next - x[i]).norm());
      x[i] = next;
    }
    result.iterations = it + 1;
    const bool gate_final = gate <= options_.final_gate_m;
    gate = std::max(0.5 * gate, options_.final_gate_m);
    if (gate_final && step < options_.converged_step_m) break;
  }

#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    float d2 = 0.0f;
    if (cloud.nearest(x[i].cast<float>(), static_cast<float>(options_.final_gate_m), &d2) >= 0) {
      result.distance_to_cloud_m[i] = std::sqrt(static_cast<double>(d2));
      result.observed[i] = result.distance_to_cloud_m[i] <= options_.observed_distance_m;
    }
  }
  return result;
}

}  // namespace tracking
