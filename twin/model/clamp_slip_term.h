#pragma once
// Clamp slip (model_effects.h "clamp_slip"): the ply slides in the jaws. Rigid jaws hold their
// patch exactly where the pose puts it (clamp.h); real jaws on a slippery prepreg let the patch
// slide along their faces under the pull of the hanging sheet, by c (m/N) per newton of the
// pull's component along the faces. Friction-limited slip is history-dependent (stick until the
// pull passes mu times the squeeze, then slide); this linear compliance is its small-load
// approximation, and what static scans can identify.
//
// When a model has clamp slip, the vertices of its clamps are not held fixed. With d_i = x_i - h_i
// the offset of patch vertex i from its held position h_i (where rigid jaws put it), a_i its
// lumped rest area, w_i = a_i / sum a its share of the patch, d = sum w_i d_i the patch's mean
// offset, and n the jaw normal (the pose's third column), P_t = I - n n^T:
//   E = 1/2 sum_i (w_i / c0) |d_i|^2 + 1/2 d^T Q d,   Q = P_t (1 / (c + c0) - 1 / c0)     (J)
// which is 1/2 sum_i (w_i / c0) |d_i - d|^2 + 1/2 d^T [P_t / (c + c0) + n n^T / c0] d:
// the patch keeps its shape as stiffly as rigid jaws hold it, and slides as one along the jaw
// faces with compliance c + c0 (pull F: offset (c + c0) P_t F + c0 n n^T F). c0 =
// kRigidJawCompliance_m_N stands for rigid jaws: at c = 0 (the effect absent) the springs are
// the per-vertex ones and give 0.1 micrometre per newton, against the millimetres scans resolve.
// The first-order change with c from there (the score test's column) is the rigid slide of each
// patch by its tangential pull, the same motion as at any c: a per-vertex compliance would
// instead first redistribute the pull inside the patch, a motion real slip does not have.
//
// E is quadratic in x: gradient and Hessian are exact. It is not linear in c:
// equilibrium_sensitivity.h differences it with a step relative to c + c0. The quadratic form
// couples every pair of a patch's vertices; the pair blocks w_i w_j Q (i != j) are a second
// EnergyTerm of arity 2 (coupling()), the vertex blocks (w_i / c0) I + w_i^2 Q this one.
//
// A released clamp holds nothing. Which clamps are engaged, and where, is set by whoever solves
// or differentiates with given poses (set_poses). The springs are built once from the clamps
// (set_clamps), so solvers' sparsity patterns stay valid.

#include <vector>

#include "twin/model/clamp.h"
#include "twin/model/energy_term.h"

namespace twin {

class ClampSlipTerm final : public EnergyTerm {
 public:
  // Compliance of rigid jaws (m/N): the patch's give at c = 0.
  static constexpr double kRigidJawCompliance_m_N = 1e-7;

  explicit ClampSlipTerm(int vertex_count);
  ClampSlipTerm(const ClampSlipTerm&) = delete;
  ClampSlipTerm& operator=(const ClampSlipTerm&) = delete;

  std::string_view name() const override { return "clamp_slip"; }
  int arity() const override { return 1; }
  const std::vector<int>& element_vertices() const override { return vertices_; }
  // The vertex blocks.
  double evaluate(const VecX& x, VecX* grad, const HessianTarget* hess, HessianMode mode) const override;
  // The pair blocks (both parts together are E).
  const EnergyTerm& coupling() const { return coupling_; }

  // Builds the springs of every gripped vertex of `clamps` on `mesh` (the model's), all engaged
  // at the clamps' identity poses. Replaces earlier ones. Call before solvers are built on the
  // model.
  void set_clamps(const SheetMesh& mesh, const ClampSet& clamps);
  bool has_clamps() const { return clamps_.size() > 0; }
  int clamp_count() const { return clamps_.size(); }
  int spring_count() const { return static_cast<int>(springs_.size()); }

  void set_compliance(double compliance_m_N) { compliance_m_N_ = compliance_m_N; }
  double compliance_m_N() const { return compliance_m_N_; }

  // Engaged clamps hold their patches at these poses (poses.size() must be clamp_count(); no
  // clamps set: nothing to do). Const because it is hold state, like the poses a solver is
  // given; throws std::invalid_argument for a wrong count.
  void set_poses(const std::vector<ClampPose>& poses) const;

 private:
  class Coupling final : public EnergyTerm {
   public:
    explicit Coupling(const ClampSlipTerm& slip) : slip_(slip) {}
    std::string_view name() const override { return "clamp_slip_coupling"; }
    int arity() const override { return 2; }
    const std::vector<int>& element_vertices() const override { return vertices_; }
    double evaluate(const VecX& x, VecX* grad, const HessianTarget* hess, HessianMode mode) const override;

   private:
    friend class ClampSlipTerm;
    const ClampSlipTerm& slip_;
    std::vector<int> vertices_;                 // per pair
    std::vector<std::array<int, 2>> springs_;  // per pair: its two springs
  };

  struct Spring {
    int clamp = 0;
    int index = 0;            // among the clamp's vertices
    double area_share = 0.0;  // w_i
  };
  // Q of the spring's clamp (zero when released).
  Mat3 softening(int clamp) const;
  Vec3 offset(const VecX& x, int spring) const { return x.segment<3>(3 * vertices_[spring]) - held_m_[spring]; }

  int vertex_count_ = 0;
  ClampSet clamps_;
  std::vector<Spring> springs_;
  std::vector<int> vertices_;
  Coupling coupling_;
  double compliance_m_N_ = 0.0;
  // From set_poses: per spring its held position (m); per clamp its jaw normal and engagement.
  mutable std::vector<Vec3> held_m_;
  mutable std::vector<Vec3> normal_;
  mutable std::vector<char> engaged_;
};

}  // namespace twin
