#pragma once
// The jaws' grip where it is more than the square pad's fixed controls (square_jaw.h): the
// lab's wide and slipping jaws (sim_hw/real_sheet/sheet_material.h) in this model's own form.
//   wide jaws      beyond the pad a square ring of width w (the material's pad_extension_m)
//                  still holds, its hold falling off across each side as a Hertzian contact
//                  pressure does: s sqrt(1 - (du/w)^2) sqrt(1 - (dv/w)^2), du and dv the material
//                  distances beyond the pad along u and v, s the material's pad_strength. The
//                  ring's outer edges are knots (jaw_knots' extension), so each element lies
//                  wholly inside it or outside and its quadrature converges as the elements do.
//   slipping jaws  the pad's controls are not fixed (fixes_controls() is false): the pad and its
//                  ring hold the ply by springs stiff across the jaw faces and compliant along
//                  them, the whole grip yielding slip_compliance_m_N (m/N) along its faces, so
//                  the ply slides and shears in the jaws under pull.
// Energy (J) per quadrature point q of the grip:
//   1/2 k A_q hold_q rho^T diag(tau, tau, 1) rho,  rho = R^T (x(q) - c) - (u - u_j, v - v_j, 0),
// k the pad stiffness (N/m^3), (c, R) the jaw's pose (columns of R: world u, v, pad normal),
// tau = min(1, 1 / (compliance k sum_q A_q hold_q)) with slip and 1 without. Quadratic in the
// controls: gradient (N) and Hessian (N/m) exact.

#include <Eigen/Core>

#include "sim_hw/real_sheet/block_sparse.h"
#include "sim_hw/real_sheet/sheet_material.h"
#include "sim_hw/spline_shell/spline_patch.h"
#include "sim_hw/spline_shell/square_jaw.h"

namespace sim_hw::spline_shell {

struct JawGrip {
  double pad_stiffness_N_m3 = 1e10;  // a 2.7 cm pad holds 3 N within half a micrometre
  double extension_m = 0, extension_strength = 0;  // wide jaws (strength 0: absent)
  double slip_compliance_m_N = 0;                  // slipping jaws (0: absent)

  bool widens() const { return extension_m > 0 && extension_strength > 0; }
  bool slips() const { return slip_compliance_m_N > 0; }
  // Without slip the pad's controls are fixed (square_jaw.h) and only the ring is springs.
  bool fixes_controls() const { return !slips(); }
  // The ring's width the knots must follow (0 without wide jaws).
  double knot_extension_m() const { return widens() ? extension_m : 0.0; }
};

// The material's jaws (pad_extension_m, pad_strength, slip_compliance_m_N). Throws
// std::invalid_argument for a negative extension, strength or compliance.
JawGrip jaw_grip(const real_sheet::SheetMaterial& material);

// The hold (0..1 times the strength) at uv: 1 on the pad, the ring's fall-off beyond it, 0 past
// the ring.
double grip_hold(const JawGrip& grip, const SquareJaw& jaw, const Vec2& uv_m);

// The grip's springs for the jaw at pose (centre, rotation): energy (J); adds the gradient into
// `gradient` and the Hessian into `hessian` when non-null. Zero (and nothing added) for a grip
// that neither widens nor slips. Without slip the pad's own points are left out: its controls
// are fixed on the rigid motion, where these springs are slack.
double grip_energy(const SplinePatch& patch, const JawGrip& grip, const SquareJaw& jaw, const Vec3& centre_m,
                   const Eigen::Matrix3d& rotation, const VecX& x, VecX* gradient,
                   real_sheet::BlockSparseMatrix* hessian);

// tau above: the share of the pad stiffness the grip keeps along the jaw faces on this patch.
double grip_tangential_share(const SplinePatch& patch, const JawGrip& grip, const SquareJaw& jaw);

}  // namespace sim_hw::spline_shell
