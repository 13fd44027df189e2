#pragma once
// A clamp's jaws as this model holds the sheet: a pad over the disk of the grip radius around
// the clamp's material point, sampled by points on rings (each with its area), each point tied
// to where the jaw carries it by a stiff spring. A point's place on the grid is bilinear in the
// cell's nodes, so the pad is resolved at every grid size and converges to rigid jaws as the
// grid is refined, whatever the grid puts under it (the twin instead fixes the vertices within
// the radius).
//
// Energy per sample s (J): 1/2 k_s rho^T diag(tau, tau, 1) rho, rho = R^T (X_s - c) - d_s, with
// X_s the sample's position on the sheet, c (m) and R (columns: world u, v, normal of the pad)
// the jaw's pose, d_s = (du, dv, 0) the sample's offset from the material point, k_s = pad
// stiffness (N/m^3) x area x hold(rho), tau the tangential share (1: rigid, < 1: the ply
// slips in the jaws). Wide jaws hold beyond the radius r out to r + w with
// hold = strength sqrt(1 - ((rho - r) / w)^2), the fall-off of a Hertzian contact pressure.
//   kRigid: the jaw's pose is prescribed (c, R).
//   kPivot: c is prescribed, R is free (a ball joint at the material point): the sheet turns in
//           the jaws as gravity pulls. R is an unknown of the solve, updated multiplicatively,
//           R <- exp([omega]x) R, with omega (rad) three extra degrees of freedom.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim_hw/real_sheet/grid.h"

namespace sim_hw::real_sheet {

enum class JawKind { kRigid, kPivot };

struct JawSample {
  Grid::Location at;
  Vec3 offset_m = Vec3::Zero();  // (du, dv, 0) in the pad's frame
  double area_m2 = 0;        // the pad area the sample stands for
  double stiffness_N_m = 0;  // pad stiffness x area x hold
};

struct JawPad {
  std::string id;
  JawKind kind = JawKind::kRigid;
  Vec2 material_point_m = Vec2::Zero();
  double grip_radius_m = 0;
  std::vector<JawSample> samples;
  double tangential_share = 1.0;  // tau
};

struct JawPadOptions {
  double grip_radius_m = 0.015;
  double pad_stiffness_N_m3 = 1e10;  // a 1.5 cm pad holds 3 N within a micrometre
  double extension_m = 0, extension_strength = 0;  // wide jaws (see the header)
  double slip_compliance_m_N = 0;                  // whole pad, along its faces
  double sample_spacing_m = 0.003;                 // at most; finer than the grid's third
};

// Throws std::invalid_argument for a negative radius or a point off the sheet.
JawPad make_jaw_pad(const Grid& grid, const std::string& id, const Vec2& material_point_m, JawKind kind,
                    const JawPadOptions& options);

// Energy (J) of the pad at jaw pose (c, R) for node positions x; adds its gradient and Hessian
// into the dense blocks over `nodes` (the pad's distinct nodes, see pad_nodes) plus, for a
// pivot, three rotation rows/columns last. g and H may be null.
double jaw_pad_energy(const JawPad& pad, const VecX& x, const Vec3& c, const Eigen::Matrix3d& R,
                      const std::vector<int>& nodes, Eigen::VectorXd* g, Eigen::MatrixXd* H);

// The distinct grid nodes the pad's samples touch, sorted.
std::vector<int> pad_nodes(const JawPad& pad);

// exp([w]x): rotation by |w| rad about w.
Eigen::Matrix3d rotation_exp(const Vec3& w);

}  // namespace sim_hw::real_sheet
