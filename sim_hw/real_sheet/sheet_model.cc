#include "sim_hw/real_sheet/sheet_model.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::real_sheet {

SheetModel::SheetModel(const Grid& grid, const SheetMaterial& material, const std::vector<Vec2>& marker_uv_m)
    : grid_(grid), material_(material) {
  const int nu = grid_.nu(), nv = grid_.nv();
  mass_kg_ = VecX::Zero(grid_.node_count());
  for (int n = 0; n < grid_.node_count(); ++n) mass_kg_[n] = material_.density_kg_m2 * grid_.node_area_m2(n);
  for (std::size_t m = 0; m < marker_uv_m.size(); ++m) {
    const Vec2& uv = marker_uv_m[m];
    if (uv.x() < -1e-6 || uv.y() < -1e-6 || uv.x() > grid_.width_m() + 1e-6 || uv.y() > grid_.height_m() + 1e-6) {
      throw std::invalid_argument(fmt::format("real sheet: marker {} at ({}, {}) m is off the sheet", m, uv.x(), uv.y()));
    }
    markers_.push_back(grid_.locate(uv));
    for (int k = 0; k < 4; ++k) mass_kg_[markers_.back().nodes[k]] += material_.marker_mass_kg * markers_.back().weights[k];
  }
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      cell_sizes_.push_back({grid_.du(i), grid_.dv(j)});
      cells_.push_back({grid_.node(i, j), grid_.node(i + 1, j), grid_.node(i + 1, j + 1), grid_.node(i, j + 1)});
    }
  }
  for (int j = 1; j + 1 < nv; ++j) {
    for (int i = 1; i + 1 < nu; ++i) {
      std::array<int, 9> s;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) s[3 * (dj + 1) + (di + 1)] = grid_.node(i + di, j + dj);
      }
      stencils_.push_back(s);
      BendingNode b;
      b.du_before_m = grid_.du(i - 1);
      b.du_after_m = grid_.du(i);
      b.dv_before_m = grid_.dv(j - 1);
      b.dv_after_m = grid_.dv(j);
      // The node's dual cell, and out to the edge for the first interior row or column.
      const double wu = 0.5 * (grid_.du(i - 1) + grid_.du(i)) + (i == 1 ? 0.5 * grid_.du(0) : 0.0) +
                        (i == nu - 2 ? 0.5 * grid_.du(nu - 2) : 0.0);
      const double wv = 0.5 * (grid_.dv(j - 1) + grid_.dv(j)) + (j == 1 ? 0.5 * grid_.dv(0) : 0.0) +
                        (j == nv - 2 ? 0.5 * grid_.dv(nv - 2) : 0.0);
      b.area_m2 = wu * wv;
      b.rest_k_1_m = rest_curvature_at(material_, grid_.rest_uv(grid_.node(i, j)));
      bending_.push_back(b);
    }
  }
}

void SheetModel::set_age_s(double age_s) { age_s_ = age_s; }

int SheetModel::pivot_count(const std::vector<JawHold>& jaws) {
  int n = 0;
  for (const JawHold& j : jaws) n += j.pad.kind == JawKind::kPivot;
  return n;
}

double SheetModel::total_weight_N() const { return mass_kg_.sum() * kGravity_m_s2; }

Vec12 SheetModel::cell_positions(const VecX& x, int c) const {
  Vec12 y;
  for (int a = 0; a < 4; ++a) y.segment<3>(3 * a) = x.segment<3>(3 * cells_[c][a]);
  return y;
}

Vec27 SheetModel::stencil_positions(const VecX& x, int b) const {
  Vec27 y;
  for (int s = 0; s < 9; ++s) y.segment<3>(3 * s) = x.segment<3>(3 * stencils_[b][s]);
  return y;
}

BlockSparseMatrix SheetModel::hessian_pattern(const std::vector<JawHold>& jaws) const {
  std::vector<std::vector<int>> groups;
  for (const auto& s : stencils_) groups.emplace_back(s.begin(), s.end());  // covers every cell too
  for (const auto& c : cells_) groups.emplace_back(c.begin(), c.end());
  int pivot = node_count();
  for (const JawHold& j : jaws) {
    std::vector<int> g = pad_nodes(j.pad);
    if (j.pad.kind == JawKind::kPivot) g.push_back(pivot++);
    groups.push_back(std::move(g));
  }
  return BlockSparseMatrix(node_count() + pivot_count(jaws), groups);
}

CellStrains SheetModel::cell_strains(const VecX& x) const {
  CellStrains e(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) e[c] = q4_strains(cell_positions(x, static_cast<int>(c)), cell_sizes_[c][0], cell_sizes_[c][1]);
  return e;
}

double SheetModel::energy(const VecX& x, const std::vector<JawHold>& jaws, VecX* g, BlockSparseMatrix* H,
                          Hessian kind, const StepTerms* step) const {
  const int n = node_count();
  if (g) *g = VecX::Zero(dof_count(jaws));
  if (H) H->set_zero();
  const double creep = material_.creep_factor(age_s_);
  Eigen::Matrix3d C = material_.membrane_C_N_m;
  C(2, 2) *= creep;
  const Eigen::Matrix3d D = creep * material_.bending_D_Nm();
  double energy = 0.0;

  // Membrane (and its viscosity over a step).
  Eigen::Matrix3d C_visc = Eigen::Matrix3d::Zero();
  if (step) C_visc.diagonal() << material_.tensile_viscosity_Ns_m, material_.tensile_viscosity_Ns_m,
      material_.shear_viscosity_Ns_m;
  const bool viscous = step && C_visc.norm() > 0;
  // Serial loops: on two shared cores, OpenMP teams per evaluation cost more in spinning
  // threads than they gained (measured on the lab's path).
  {
    for (int c = 0; c < static_cast<int>(cells_.size()); ++c) {
      const Vec12 y = cell_positions(x, c);
      Vec12 gc;
      Mat12 hc;
      for (int pass = 0; pass < (viscous ? 2 : 1); ++pass) {
        energy += pass == 0 ? q4_membrane_energy(y, cell_sizes_[c][0], cell_sizes_[c][1], C, nullptr, g ? &gc : nullptr,
                                                 H ? &hc : nullptr, kind)
                            : q4_membrane_energy(y, cell_sizes_[c][0], cell_sizes_[c][1], C_visc / step->dt_s, &step->strain_start[c],
                                                 g ? &gc : nullptr, H ? &hc : nullptr, kind);
        if (g) {
          for (int a = 0; a < 4; ++a) g->segment<3>(3 * cells_[c][a]) += gc.segment<3>(3 * a);
        }
        if (H) H->add(cells_[c].data(), 4, hc);
      }
    }
  }

  // Bending.
  {
    for (int b = 0; b < static_cast<int>(stencils_.size()); ++b) {
      Vec27 gb;
      Mat27 hb;
      energy += curvature_bending_energy(stencil_positions(x, b), bending_[b], D, material_.stiffening_m2,
                                         g ? &gb : nullptr, H ? &hb : nullptr, kind);
      if (g) {
        for (int s = 0; s < 9; ++s) g->segment<3>(3 * stencils_[b][s]) += gb.segment<3>(3 * s);
      }
      if (H) H->add(stencils_[b].data(), 9, hb);
    }
  }

  // Gravity along -z.
  for (int i = 0; i < n; ++i) {
    energy += mass_kg_[i] * kGravity_m_s2 * x[3 * i + 2];
    if (g) (*g)[3 * i + 2] += mass_kg_[i] * kGravity_m_s2;
  }

  // Jaws.
  int pivot = n;
  for (const JawHold& j : jaws) {
    std::vector<int> blocks = pad_nodes(j.pad);
    const bool is_pivot = j.pad.kind == JawKind::kPivot;
    const int size = 3 * static_cast<int>(blocks.size()) + (is_pivot ? 3 : 0);
    Eigen::VectorXd gj = Eigen::VectorXd::Zero(g ? size : 0);
    Eigen::MatrixXd hj = Eigen::MatrixXd::Zero(H ? size : 0, H ? size : 0);
    energy += jaw_pad_energy(j.pad, x, j.centre_m, j.rotation, blocks, g ? &gj : nullptr, H ? &hj : nullptr);
    if (is_pivot) blocks.push_back(pivot++);
    if (g) {
      for (std::size_t k = 0; k < blocks.size(); ++k) g->segment<3>(3 * blocks[k]) += gj.segment<3>(3 * k);
    }
    if (H) H->add(blocks, hj);
  }

  // Implicit step: inertia and drag.
  if (step) {
    const double dt = step->dt_s;
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(H ? H->size() : 0);
    for (int i = 0; i < n; ++i) {
      const double m = mass_kg_[i];
      const Vec3 xi = x.segment<3>(3 * i);
      const Vec3 inertial = xi - step->x_start.segment<3>(3 * i) - dt * step->v_start.segment<3>(3 * i);
      const Vec3 moved = xi - step->x_start.segment<3>(3 * i);
      const double drag = material_.mass_damping_1_s * m / dt;
      energy += 0.5 * m / (dt * dt) * inertial.squaredNorm() + 0.5 * drag * moved.squaredNorm();
      if (g) g->segment<3>(3 * i) += m / (dt * dt) * inertial + drag * moved;
      if (H) diagonal.segment<3>(3 * i).setConstant(m / (dt * dt) + drag);
    }
    if (H) H->add_to_diagonal(diagonal);
  }
  return energy;
}

std::vector<Vec3> SheetModel::marker_positions(const VecX& x) const {
  std::vector<Vec3> p;
  for (const auto& at : markers_) p.push_back(grid_.position(x, at));
  return p;
}

Vec3 SheetModel::normal_at(const VecX& x, const Vec2& uv_m) const {
  const Grid::Location at = grid_.locate(uv_m);
  // Cell corners 0..3 counter-clockwise; x_u ~ (x1 - x0) + (x2 - x3), x_v ~ (x3 - x0) + (x2 - x1).
  const auto p = [&](int k) { return Vec3(x.segment<3>(3 * at.nodes[k])); };
  const Vec3 xu = p(1) - p(0) + p(2) - p(3), xv = p(3) - p(0) + p(2) - p(1);
  return xu.cross(xv).normalized();
}

}  // namespace sim_hw::real_sheet
