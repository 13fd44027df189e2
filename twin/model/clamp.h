#pragma once
// Clamps: each grips a patch of the sheet and holds it at a world pose.
//
// A clamp is defined on the material: a point (u, v) (m) and a grip radius (m). It grips every
// vertex within the radius of the point, and at least the three vertices of the triangle
// holding the point (jaws resist turning, also on a mesh coarser than the jaws); with radius
// zero it is a pin that holds only the nearest vertex. While engaged it holds the gripped patch rigidly in
// its rest shape: vertex i goes to  p + R (u_i - u_c, v_i - v_c, 0),  with p the clamp's world
// position (m) and R its orientation (columns: world directions of the material u, v and the
// sheet normal at the clamp). A released clamp holds nothing. Poses may change every step.

#include <array>
#include <string>
#include <vector>

#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

struct ClampSpec {
  std::string id;
  Vec2 material_point_m = Vec2::Zero();
  double grip_radius_m = 0.0;
};

struct ClampPose {
  Vec3 position_m = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  bool engaged = true;
};

// Pose a fraction t in [0, 1] of the way from a to b (position linear, rotation slerp); engaged
// as b is.
ClampPose interpolate(const ClampPose& a, const ClampPose& b, double t);

class Clamp {
 public:
  // Throws std::invalid_argument naming the clamp if its point is not on the sheet or its
  // radius is negative or non-finite.
  Clamp(const SheetMesh& mesh, const ClampSpec& spec);
  const ClampSpec& spec() const { return spec_; }
  const std::vector<int>& vertices() const { return vertices_; }
  // The rest triangle holding the material point (always among the gripped vertices).
  const std::array<int, 3>& host_triangle() const { return host_triangle_; }
  // Writes the held positions of the gripped vertices into x (3n).
  void hold(const ClampPose& pose, VecX& x) const;
  // Held position (m) of vertices()[k] at `pose`.
  Vec3 held_position(int k, const ClampPose& pose) const {
    return pose.position_m + pose.rotation.leftCols<2>() * offsets_m_[k];
  }
  // Where the clamp's material point is in the sheet at positions x (m): where the clamp grips
  // when it closes on the sheet as it is.
  Vec3 material_point_position(const VecX& x) const;
  // Orientation of the material there (columns: world directions of u, v and the normal, from
  // the polar decomposition of the host triangle's deformation): how a clamp closing on the
  // sheet as it is finds the patch turned.
  Mat3 material_frame(const VecX& x) const;

 private:
  ClampSpec spec_;
  std::vector<int> vertices_;
  std::vector<Vec2> offsets_m_;  // u_i - u_c
  std::array<int, 3> host_triangle_{};  // rest triangle holding the material point
  Vec3 host_weights_ = Vec3::Zero();     // its barycentric coordinates there
  Eigen::Matrix<double, 3, 2> host_gradients_ = Eigen::Matrix<double, 3, 2>::Zero();  // 1/m
};

class ClampSet {
 public:
  ClampSet() = default;
  // Throws std::invalid_argument for duplicate ids or two clamps gripping the same vertex.
  ClampSet(const SheetMesh& mesh, const std::vector<ClampSpec>& specs);

  int size() const { return static_cast<int>(clamps_.size()); }
  const Clamp& operator[](int i) const { return clamps_[i]; }
  // Index of the clamp with this id; throws std::invalid_argument naming it if unknown.
  int index_of(const std::string& id) const;

  // fixed[v] = 1 for every vertex gripped by an engaged clamp. poses.size() == size().
  std::vector<char> fixed_vertices(int vertex_count, const std::vector<ClampPose>& poses) const;
  // Writes the held positions of every engaged clamp into x.
  void hold(const std::vector<ClampPose>& poses, VecX& x) const;

 private:
  std::vector<Clamp> clamps_;
};

// World placement of the flat sheet: material point (0, 0) at `origin_m`; the columns of
// `rotation` are the world directions of u, v and the sheet normal.
struct SheetPlacement {
  Vec3 origin_m = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  Vec3 to_world(const Vec2& uv) const { return origin_m + rotation.leftCols<2>() * uv; }
};

// Positions (3n) of the sheet lying flat as placed.
VecX place_flat(const SheetMesh& mesh, const SheetPlacement& placement);

}  // namespace twin
