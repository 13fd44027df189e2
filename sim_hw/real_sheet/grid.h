#pragma once
// The independent sheet's discretisation: a rectangle [0, W] x [0, H] of material coordinates
// (u across = weft, v up = warp, metres) sampled on a regular grid of nu x nv nodes with
// spacings du = W / (nu - 1), dv = H / (nv - 1). Node (i, j) sits at (i du, j dv); nodes are
// numbered row-major, node = j nu + i, and positions are stacked [x0 y0 z0 x1 ...] (m, world
// frame, z up).
//
// This is the "real sheet" of the scanner lab and the fake world (issue 33): a discretisation of
// a different family from the twin's (bilinear quadrilaterals and finite-difference curvature on
// a structured grid, against the twin's constant-strain triangles and hinge angles on an
// offset-row triangulation). It shares no mesh, energy or solver code with twin/.

#include <array>

#include <Eigen/Core>

namespace sim_hw::real_sheet {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using VecX = Eigen::VectorXd;

class Grid {
 public:
  // The coarsest grid whose spacings are at most `max_spacing_m` in both directions (at least
  // 3 x 3 nodes). Throws std::invalid_argument for a non-positive or non-finite size.
  Grid(double width_m, double height_m, double max_spacing_m);

  int nu() const { return nu_; }
  int nv() const { return nv_; }
  int node_count() const { return nu_ * nv_; }
  int node(int i, int j) const { return j * nu_ + i; }
  double du() const { return du_; }
  double dv() const { return dv_; }
  double width_m() const { return width_m_; }
  double height_m() const { return height_m_; }
  Vec2 rest_uv(int node) const { return Vec2((node % nu_) * du_, (node / nu_) * dv_); }
  // Area of the node's dual cell (m^2): du dv inside, half on an edge, a quarter at a corner.
  double node_area_m2(int node) const;
  // The flat sheet in the plane z = 0 with x, y = u, v.
  VecX flat_positions() const;

  // A material point as a bilinear combination of the four nodes of the cell holding it.
  // Points off the sheet are moved onto its nearest edge.
  struct Location {
    std::array<int, 4> nodes{};
    std::array<double, 4> weights{};
  };
  Location locate(const Vec2& uv_m) const;
  Vec3 position(const VecX& x, const Location& at) const;

 private:
  double width_m_ = 0, height_m_ = 0, du_ = 0, dv_ = 0;
  int nu_ = 0, nv_ = 0;
};

}  // namespace sim_hw::real_sheet
