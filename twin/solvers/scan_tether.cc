#include "twin/solvers/scan_tether.h"

#include <cmath>
#include <stdexcept>

#include "twin/model/hessian_pattern.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/objective.h"
#include "twin/solvers/sparse_cholesky.h"
#include "twin/solvers/static_solver.h"

namespace twin {
namespace {

// Whether x is a stable equilibrium of the model: its exact Hessian over the free DOFs is
// positive definite (Cholesky succeeds). Newton with a definiteness fix descends the energy but
// can still stop on a saddle that the last, weak springs held up; a real sheet never rests there.
bool stable(const ShellModel& model, const DofMap& dofs, const VecX& x) {
  const Objective potential(model.potential_terms());
  HessianPattern hessian(dofs, potential.stencils());
  potential.evaluate(x, nullptr, &hessian, HessianMode::kExact);
  SparseCholesky cholesky;
  cholesky.analyze(hessian.matrix());
  return cholesky.factorize(hessian.matrix());
}

}  // namespace

MarkerTetherTerm::MarkerTetherTerm(const MaterialPointMap& markers, const std::vector<Vec3>& observed_m,
                                   int vertex_count) {
  std::vector<int> vertices;
  for (int m = 0; m < markers.size() && m < static_cast<int>(observed_m.size()); ++m) {
    if (!observed_m[m].allFinite()) continue;
    const MaterialPointLocation& at = markers.location(m);
    vertices.insert(vertices.end(), at.vertices.begin(), at.vertices.end());
    weights_.push_back(at.weights);
    targets_m_.push_back(observed_m[m]);
  }
  set_elements(std::move(vertices), vertex_count);
}

double MarkerTetherTerm::element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                                        HessianMode) const {
  const Vec3& w = weights_[e];
  const Vec3 r = w(0) * xe.segment<3>(0) + w(1) * xe.segment<3>(3) + w(2) * xe.segment<3>(6) - targets_m_[e];
  if (g) {
    for (int a = 0; a < 3; ++a) g->segment<3>(3 * a) = k_N_m_ * w(a) * r;
  }
  if (h) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) h->block<3, 3>(3 * a, 3 * b) = k_N_m_ * w(a) * w(b) * Mat3::Identity();
    }
  }
  return 0.5 * k_N_m_ * r.squaredNorm();
}

SolveReport equilibrium_from_scan(const ShellModel& model, const ClampSet& clamps,
                                  const std::vector<ClampPose>& poses, const MaterialPointMap& markers,
                                  const std::vector<Vec3>& observed_m, VecX& x,
                                  const TetherRelease& release) {
  const DofMap dofs = model.hold_clamps(clamps, poses);
  const double force_scale_N = free_weight_N(model, dofs);
  MarkerTetherTerm tether(markers, observed_m, model.vertex_count());
  std::vector<const EnergyTerm*> terms = model.potential_terms();
  terms.push_back(&tether);
  const Objective tethered(terms);
  NewtonSolver newton;
  NewtonOptions options = default_static_options();
  options.residual_tolerance = 1e-6;  // intermediate shapes need not be exact
  VecX current = x;
  clamps.hold(poses, current);
  SolveReport total;
  // Spring stiffness per marker, relative to the marker's share of the sheet's weight per metre
  // of stretch (the default starts at "a 1 mm pull holds ten times its weight").
  const double weight_per_marker_N = force_scale_N / std::sqrt(static_cast<double>(std::max(1, markers.size())));
  if (!(release.first >= release.last && release.last > 0.0 && release.ratio > 1.0)) {
    throw std::invalid_argument("equilibrium_from_scan: the tether release needs first >= last > 0 and ratio > 1");
  }
  for (double factor = release.first; factor >= release.last * (1.0 - 1e-9); factor /= release.ratio) {
    tether.set_stiffness(factor * weight_per_marker_N);
    total.append(newton.minimize(tethered, dofs, force_scale_N, current, options));
    if (!total.usable()) {
      total.message = "tethered to the scan: " + total.message;
      return total;
    }
  }
  StaticSolver statics(model);
  total.append(statics.solve(clamps, poses, current));
  if (total.usable() && !stable(model, dofs, current)) {
    total.status = SolveStatus::kIndefinite;
    total.message = "let go of the scan onto an unstable equilibrium (the exact Hessian is not positive definite)";
  }
  if (total.usable()) x.swap(current);
  return total;
}

}  // namespace twin
