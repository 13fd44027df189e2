#pragma once
// The structured mesh of eight-node quadratic shell elements (CalculiX S8R) on a rectangular
// sheet that the CalculiX opinion of the reference uses (docs/reference_sheet.md, "CalculiX's
// opinion"): element edges at every cut asked for (the jaws' pad edges, so a pad is a set of
// whole elements and its hold is exact) and between cuts spans of equal length no longer than
// the element size. Nodes are the corners and mid-sides of the elements, numbered from 1 row by
// row; an element's nodes are in CalculiX's order (corners anticlockwise from (u-, v-), then the
// mid-sides of the edges 1-2, 2-3, 3-4, 4-1), so its normal is +w of the material frame.

#include <array>
#include <vector>

#include <Eigen/Core>

namespace sim_hw::calculix {

using Vec2 = Eigen::Vector2d;

class ShellGrid {
 public:
  // Throws std::invalid_argument for a non-positive size or element size, or a cut off the sheet.
  ShellGrid(double width_m, double height_m, double element_size_m, std::vector<double> u_cuts_m,
            std::vector<double> v_cuts_m);

  const std::vector<double>& u_lines_m() const { return u_lines_; }
  const std::vector<double>& v_lines_m() const { return v_lines_; }
  int element_count() const { return eu() * ev(); }
  int node_count() const { return node_count_; }
  // Node id (1-based) of lattice point (i, j), i in [0, 2 eu], j in [0, 2 ev]; -1 at an
  // element's centre (S8R has no node there).
  int node_id(int i, int j) const { return lattice_id_[j * (2 * eu() + 1) + i]; }
  Vec2 node_uv_m(int id) const { return node_uv_[id - 1]; }
  // Element e (0-based, row by row) as CalculiX node ids.
  std::array<int, 8> element_nodes(int e) const;

  // The element holding material point uv (clamped onto the sheet) and its coordinates (xi, eta)
  // in [-1, 1]^2.
  struct Location {
    int element = 0;
    double xi = 0, eta = 0;
  };
  Location locate(const Vec2& uv_m) const;

 private:
  int eu() const { return static_cast<int>(u_lines_.size()) - 1; }
  int ev() const { return static_cast<int>(v_lines_.size()) - 1; }
  std::vector<double> u_lines_, v_lines_;
  std::vector<int> lattice_id_;
  std::vector<Vec2> node_uv_;
  int node_count_ = 0;
};

// The serendipity shape functions of the eight-node quadrilateral at (xi, eta), in the element's
// node order.
std::array<double, 8> s8_shape(double xi, double eta);

}  // namespace sim_hw::calculix
