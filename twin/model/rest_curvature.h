#pragma once
// Hinge rest angles of a sheet that is curved at rest (a roll set), from its rest curvature
// tensor K0 (1/m) in the material frame (u, v):
//   K0 = [[uu, uv], [uv, vv]],   rest surface w(u, v) = 1/2 (u, v) K0 (u, v)^T
// with w measured along the triangles' normal (+w for the counter-clockwise (u, v) triangles of
// sheet_mesh.h, so K0 > 0 curls the sheet towards that side).
//
// The rest angle of a hinge is the dihedral angle (dihedral_angle.h) of its four rest vertices
// lifted onto that surface, linearised in the lift: theta_rest = sum_k dtheta/dw_k w_k, with
// dtheta/dw_k the out-of-plane part of the dihedral angle's gradient at the flat rest hinge.
// Linear and translation-free: adding a plane a + b.(u, v) to w is a rigid motion of the flat
// hinge and leaves theta unchanged to first order, so the reference point of (u, v) does not
// matter. This is exact to first order in K0 times the hinge size, and it is linear in K0
// (identification differences the gradient forward in K0 and relies on that). The sign follows
// dihedral_angle.h: lifting the wings makes theta negative, so K0 > 0 gives negative angles.
//
// Why not theta_rest = -n^T K0 (c_b - c_a) (n the edge's in-plane normal, c the rest centroids):
// that is the angle between the smooth surface's normals at the centroids, but the hinge angle
// is between the flat triangles' normals, i.e. the secant slopes of the interpolated surface. On
// an equilateral hinge of heights h, a cylinder across the edge gives |theta| = kappa h, the
// centroid formula 2/3 of it, which would leave a wrapped sheet with 1/9 of its bending energy.
// The linearised form is tested against the dihedral angle of the lifted hinge (relative
// difference below 1e-4) and against sheets wrapped on cylinders (energy below 1e-5 of unset).
//
// Several curvatures at once (K0_uu and K0_vv both non-zero) describe a doubly curved rest shape
// that a flat rest membrane cannot take without stretching: the sheet then keeps some internal
// stress at rest, as a real ply with such a set would.
//
// The same coefficients give each hinge's angle per unit curvature across it,
// t_e = theta_rest(K0 = n n^T) with n the hinge's unit normal in (u, v): the length (m) that
// converts a hinge angle to a curvature (used by bending stiffening).

#include <vector>

#include "twin/model/hinge_bending.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

// A rest curvature tensor (1/m), material frame.
struct CurvatureTensor {
  double uu_1_m = 0.0;
  double vv_1_m = 0.0;
  double uv_1_m = 0.0;
  bool operator==(const CurvatureTensor&) const = default;
};

class HingeCurvatureMap {
 public:
  // Throws std::invalid_argument for a degenerate rest hinge (naming it).
  HingeCurvatureMap(const SheetMesh& mesh, const std::vector<Hinge>& hinges);

  int hinge_count() const { return static_cast<int>(coefficients_.size()); }
  // theta_rest (rad) of hinge e for rest curvature k; linear in k.
  double rest_angle(int e, const CurvatureTensor& k) const {
    const Vec3& a = coefficients_[e];
    return a(0) * k.uu_1_m + a(1) * k.vv_1_m + a(2) * k.uv_1_m;
  }
  std::vector<double> rest_angles(const CurvatureTensor& k) const;
  // |t_e| (m): |hinge angle| per unit curvature across hinge e (positive).
  const std::vector<double>& across_lengths_m() const { return across_m_; }
  // Unit normal of hinge e's edge in (u, v).
  const std::vector<Vec2>& normals() const { return normals_; }
  // dtheta_rest / d(K0_uu, K0_vv, K0_uv) of hinge e (m).
  const Vec3& coefficients(int e) const { return coefficients_[e]; }

 private:
  std::vector<Vec3> coefficients_;
  std::vector<double> across_m_;
  std::vector<Vec2> normals_;
};

}  // namespace twin
