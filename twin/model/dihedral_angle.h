#pragma once
// Signed dihedral angle of a hinge and its exact first and second derivatives, after Tamstorf and
// Grinspun, "Discrete bending forces and their Jacobians", Graphical Models 2013.
//
// Hinge: shared edge (x0, x1); triangle A = (x0, x1, x2) and triangle B = (x1, x0, x3), both
// counter-clockwise, so their normals agree when the hinge is flat. With e = x1 - x0,
//   nA = e x (x2 - x0),  nB = (x3 - x0) x e,  theta = atan2((nA^ x nB^) . e^, nA^ . nB^)
// theta = 0 when flat; lifting x2 or x3 along its triangle's normal makes theta negative.
//
// Gradient: for each triangle T with unit normal n_T, height h_T of its free vertex over the
// hinge line and foot parameter s_T = (x_free - x0).e / |e|^2, vertex k of T receives
// c_Tk n_T with c = ((1 - s_T)/h_T, s_T/h_T, -1/h_T) for (x0, x1, x_free).
// Hessian: differentiating c_Tk n_T, with d n_T / d x_j = -grad phi_Tj n_T^T (phi the hat
// functions of T; only out-of-plane motion turns the normal) and d c_Tk / d x_j in the plane of T
// (c depends on lengths only); the closed forms are in dihedral_angle.cc.
// DOF order of the 12-vectors: (x0, x1, x2, x3), each (x, y, z).

#include "twin/base/types.h"

namespace twin {

// Returns theta (rad); NaN if either triangle is degenerate. Writes gradient (1/m) and Hessian
// (1/m^2) when non-null.
double dihedral_angle(const Vec12& xh, Vec12* grad, Mat12* hess);

}  // namespace twin
