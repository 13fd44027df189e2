#pragma once
// The independent sheet's discretisation: a rectangle [0, W] x [0, H] of material coordinates
// (u across = weft, v up = warp, metres) cut by grid lines u_0 = 0 < u_1 < ... < u_{nu-1} = W and
// v_0 = 0 < ... < v_{nv-1} = H, uniform or graded: fine near the clamps' jaws (lines through
// every jaw's centre, a fixed number of cells across its radius) and near the free edges,
// growing geometrically to the largest spacing elsewhere. Node (i, j) sits at (u_i, v_j); nodes
// are numbered row-major, node = j nu + i, and positions are stacked [x0 y0 z0 x1 ...] (m, world
// frame, z up).
//
// This is the "real sheet" of the scanner lab and the fake world (issue 33): a discretisation of
// a different family from the twin's (bilinear quadrilaterals and finite-difference curvature on
// a tensor-product grid, against the twin's constant-strain triangles and hinge angles on an
// offset-row triangulation). It shares no mesh, energy or solver code with twin/.

#include <array>
#include <vector>

#include <Eigen/Core>

namespace sim_hw::real_sheet {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using VecX = Eigen::VectorXd;

// Where a graded grid is fine along one axis: lines at `at_m` + k `spacing_m` for |k spacing|
// <= reach_m, then cells growing by the grid's growth factor.
struct GridAttractor {
  double at_m = 0;
  double spacing_m = 0.005;
  double reach_m = 0;
};

// Grid lines on [0, length]: through 0, length and every attractor's fine zone, elsewhere
// spaced by min(max_spacing, attractor spacing growing geometrically with the distance).
std::vector<double> graded_lines(double length_m, double max_spacing_m, const std::vector<GridAttractor>& attractors,
                                 double growth = 1.25);

class Grid;

// A grid fine where a hanging sheet bends most sharply and where the discretisation's
// first-order errors sit: at the jaws' edges and at the free edges. Lines through every jaw's
// centre with spacing max/4 within 1.5 radii of it and at the sheet's edges, growing by 1.25 per
// cell to `max_spacing_m` elsewhere; halving max_spacing_m halves every spacing.
struct JawSpot {
  Vec2 material_point_m = Vec2::Zero();
  double radius_m = 0;
};
Grid graded_grid(double width_m, double height_m, const std::vector<JawSpot>& jaws, double max_spacing_m);

class Grid {
 public:
  // Uniform: the coarsest grid whose spacings are at most `max_spacing_m` (at least 3 x 3
  // nodes). Throws std::invalid_argument for a non-positive or non-finite size.
  Grid(double width_m, double height_m, double max_spacing_m);
  // Given lines (each increasing from 0, at least three). Throws std::invalid_argument otherwise.
  Grid(std::vector<double> u_lines_m, std::vector<double> v_lines_m);

  int nu() const { return static_cast<int>(u_.size()); }
  int nv() const { return static_cast<int>(v_.size()); }
  int node_count() const { return nu() * nv(); }
  int node(int i, int j) const { return j * nu() + i; }
  double u(int i) const { return u_[i]; }
  double v(int j) const { return v_[j]; }
  double du(int i) const { return u_[i + 1] - u_[i]; }  // cell column i
  double dv(int j) const { return v_[j + 1] - v_[j]; }  // cell row j
  double max_spacing_m() const;
  double min_spacing_m() const;
  double width_m() const { return u_.back(); }
  double height_m() const { return v_.back(); }
  Vec2 rest_uv(int node) const { return Vec2(u_[node % nu()], v_[node / nu()]); }
  // Area of the node's dual cell (m^2): half of each neighbouring spacing in u times in v.
  double node_area_m2(int node) const;
  // The flat sheet in the plane z = 0 with x, y = u, v.
  VecX flat_positions() const;

  // A material point as a bilinear combination of the four nodes of the cell holding it
  // (counter-clockwise from (i, j)). Points off the sheet are moved onto its nearest edge.
  struct Location {
    std::array<int, 4> nodes{};
    std::array<double, 4> weights{};
  };
  Location locate(const Vec2& uv_m) const;
  Vec3 position(const VecX& x, const Location& at) const;
  // The surface through the nodes by tensor-product cubic Lagrange interpolation over the 4 x 4
  // nodes around the point's cell (shifted inward at the edges): nearly smooth across cells,
  // where the bilinear surface has kinks a finer grid's curvature would see.
  Vec3 smooth_position(const VecX& x, const Vec2& uv_m) const;
  // The sizes (du, dv) of the cell holding a material point.
  Vec2 cell_size_at(const Vec2& uv_m) const;

 private:
  std::vector<double> u_, v_;
};

}  // namespace sim_hw::real_sheet
