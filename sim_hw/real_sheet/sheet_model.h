#pragma once
// The independent sheet's total potential, assembled over the grid: Q4 membrane cells,
// curvature bending at interior nodes, gravity on lumped node masses (and marker masses), the
// jaws' pads, and, for a dynamic step, inertia, drag and strain-rate viscosity as the implicit
// step's incremental potential.
//
// Unknowns: the node positions (3 per node, grid order), then three rotation unknowns per pivot
// jaw in the order the jaws are listed (see jaw_pad.h). Energy in J, gradient in N (N*m for
// rotations), Hessian in N/m.
//
// Bending at free edges: a node on the sheet's edge has no centred stencil, so the first
// interior row's and column's nodes also carry the half cells out to the edge: the edge's
// curvature is taken as the first interior node's (a first-order error in the edge spacing,
// which is why graded grids are fine at the edges).

#include <array>
#include <vector>

#include <Eigen/Core>

#include "sim_hw/real_sheet/block_sparse.h"
#include "sim_hw/real_sheet/curvature_bending.h"
#include "sim_hw/real_sheet/grid.h"
#include "sim_hw/real_sheet/jaw_pad.h"
#include "sim_hw/real_sheet/membrane_q4.h"
#include "sim_hw/real_sheet/sheet_material.h"

namespace sim_hw::real_sheet {

// A pad held at a pose: c (m) and R (columns: world directions of the pad's u, v and normal).
// For a pivot jaw R is the jaw's current turn, an unknown the solver updates.
struct JawHold {
  JawPad pad;
  Vec3 centre_m = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

using CellStrains = std::vector<std::array<Eigen::Vector3d, 4>>;

// One implicit (backward Euler) step of dt from positions x_start with velocities v_start: the
// potential adds sum m |x - x_start - dt v_start|^2 / (2 dt^2) (inertia), alpha m |x - x_start|^2
// / (2 dt) (drag) and the membrane's viscous dissipation from the cells' strains at the start.
struct StepTerms {
  double dt_s = 1.0 / 30;
  VecX x_start, v_start;
  CellStrains strain_start;
};

class SheetModel {
 public:
  // Throws std::invalid_argument for a marker off the sheet.
  SheetModel(const Grid& grid, const SheetMaterial& material, const std::vector<Vec2>& marker_uv_m = {});

  const Grid& grid() const { return grid_; }
  const SheetMaterial& material() const { return material_; }
  // Creep: shear and bending at `age_s` after the clamps last moved (NaN: long after).
  void set_age_s(double age_s);
  double age_s() const { return age_s_; }

  int node_count() const { return grid_.node_count(); }
  static int pivot_count(const std::vector<JawHold>& jaws);
  int dof_count(const std::vector<JawHold>& jaws) const { return 3 * (node_count() + pivot_count(jaws)); }
  // Node masses (kg): the sheet's density over each node's cell, plus the markers' masses.
  const VecX& node_mass_kg() const { return mass_kg_; }
  double total_weight_N() const;

  BlockSparseMatrix hessian_pattern(const std::vector<JawHold>& jaws) const;
  double energy(const VecX& x, const std::vector<JawHold>& jaws, VecX* gradient, BlockSparseMatrix* hessian,
                Hessian kind, const StepTerms* step = nullptr) const;
  CellStrains cell_strains(const VecX& x) const;

  // The markers (material points given at construction) on the sheet at x.
  std::vector<Vec3> marker_positions(const VecX& x) const;
  const std::vector<Grid::Location>& marker_locations() const { return markers_; }
  // The sheet's unit normal at a material point (x_u cross x_v of the bilinear cell).
  Vec3 normal_at(const VecX& x, const Vec2& uv_m) const;

 private:
  Vec12 cell_positions(const VecX& x, int cell) const;
  Vec27 stencil_positions(const VecX& x, int b) const;

  Grid grid_;
  SheetMaterial material_;
  double age_s_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<Grid::Location> markers_;
  VecX mass_kg_;
  std::vector<std::array<int, 4>> cells_;
  std::vector<std::array<double, 2>> cell_sizes_;  // (du, dv) per cell, m
  std::vector<std::array<int, 9>> stencils_;
  std::vector<BendingNode> bending_;
};

}  // namespace sim_hw::real_sheet
