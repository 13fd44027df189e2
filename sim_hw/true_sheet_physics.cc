#include "sim_hw/true_sheet_physics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/real_sheet/equilibrium_solver.h"
#include "sim_hw/real_sheet/sheet_model.h"
#include "twin/solvers/implicit_stepper.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace sim_hw {
namespace {

// The twin's own shell model, as the world ran before issue 33.
class TwinPhysics final : public TrueSheetPhysics {
 public:
  TwinPhysics(const twin::SheetMesh& mesh, const twin::Material& material) : model_(mesh, material) {}

  const twin::SheetMesh& mesh() const override { return model_.mesh(); }

  Settled settle(const std::vector<twin::ClampSpec>& specs, const std::vector<twin::ClampPose>& poses,
                 twin::VecX& x) override {
    twin::ClampSet set;
    try {
      set = twin::ClampSet(model_.mesh(), specs);
    } catch (const std::invalid_argument& e) {
      return {e.what(), 0};
    }
    model_.set_clamps_of_material_effects(set);  // only for the clamp effects the material has
    twin::StaticSolver statics(model_);
    twin::VecX y = x;
    const twin::SolveReport report = statics.solve(set, poses, y);
    if (!report.usable()) {
      return {to_string(report.status) + (report.message.empty() ? "" : ": " + report.message), report.iterations};
    }
    x = y;
    return {"", report.iterations};
  }

  std::string step(const std::vector<twin::ClampSpec>& specs, const std::vector<twin::ClampPose>& poses,
                   bool specs_changed, double dt_s, twin::VecX& x, twin::VecX& v) override {
    if (specs_changed || !clamps_) {
      // A new set of holding clamps; a fresh stepper takes each clamp's start from the sheet.
      try {
        clamps_ = std::make_unique<twin::ClampSet>(model_.mesh(), specs);
        model_.set_clamps_of_material_effects(*clamps_);  // before the stepper builds its pattern
        stepper_ = std::make_unique<twin::ImplicitStepper>(model_);
      } catch (const std::invalid_argument& e) {
        clamps_.reset();
        return e.what();
      }
    }
    const twin::SolveReport report = stepper_->step(x, v, dt_s, *clamps_, poses, twin::linearized_step_options());
    if (!report.usable()) return report.message.empty() ? to_string(report.status) : report.message;
    return "";
  }

  bool clamps_compatible(const std::vector<twin::ClampSpec>& specs) const override {
    try {
      const twin::ClampSet check(model_.mesh(), specs);  // refuses a patch another clamp holds
      return true;
    } catch (const std::invalid_argument&) {
      return false;
    }
  }

  Eigen::Isometry3d patch_pose(const twin::ClampSpec& spec, const twin::VecX& x) const override {
    const twin::Clamp clamp(model_.mesh(), spec);
    Eigen::Isometry3d patch = Eigen::Isometry3d::Identity();
    patch.translation() = clamp.material_point_position(x);
    patch.linear() = clamp.material_frame(x);
    return patch;
  }

  int last_substeps() const override { return stepper_ ? stepper_->last_substeps() : 1; }

 private:
  twin::ShellModel model_;
  std::unique_ptr<twin::ClampSet> clamps_;
  std::unique_ptr<twin::ImplicitStepper> stepper_;
};

// The independent plate (real_sheet/), its grid shown to the cameras as two triangles per cell.
class IndependentPhysics final : public TrueSheetPhysics {
 public:
  IndependentPhysics(double width_m, double height_m, const twin::Material& material, double spacing_m)
      : model_(real_sheet::Grid(width_m, height_m, spacing_m), real_sheet::sheet_material_from(material)) {
    const real_sheet::Grid& grid = model_.grid();
    for (int n = 0; n < grid.node_count(); ++n) mesh_.rest_uv.push_back(grid.rest_uv(n));
    for (int j = 0; j + 1 < grid.nv(); ++j) {
      for (int i = 0; i + 1 < grid.nu(); ++i) {
        const int a = grid.node(i, j), b = grid.node(i + 1, j), c = grid.node(i + 1, j + 1), d = grid.node(i, j + 1);
        mesh_.triangles.push_back({a, b, c});
        mesh_.triangles.push_back({a, c, d});
      }
    }
  }

  const twin::SheetMesh& mesh() const override { return mesh_; }

  Settled settle(const std::vector<twin::ClampSpec>& specs, const std::vector<twin::ClampPose>& poses,
                 twin::VecX& x) override {
    std::vector<real_sheet::JawHold> jaws = holds(specs, poses);
    real_sheet::EquilibriumOptions o;
    o.initial_damping_1_s2 = 1e4;  // the hand-over: the sheet falls into its hold, overdamped
    o.max_iterations = 5000;
    const real_sheet::EquilibriumReport r = real_sheet::solve_equilibrium(model_, x, jaws, o);
    return {r.converged ? "" : r.message, r.iterations};
  }

  std::string step(const std::vector<twin::ClampSpec>& specs, const std::vector<twin::ClampPose>& poses, bool,
                   double dt_s, twin::VecX& x, twin::VecX& v) override {
    std::vector<real_sheet::JawHold> jaws = holds(specs, poses);
    real_sheet::StepTerms terms;
    terms.dt_s = dt_s;
    terms.x_start = x;
    terms.v_start = v;
    terms.strain_start = model_.cell_strains(x);
    // Linearised backward Euler (one Newton iteration on the step's potential, with the
    // projected Hessian, accepted when it lowered that potential), as a real-time step can afford.
    real_sheet::EquilibriumOptions o;
    o.max_iterations = 1;
    o.keep_on_limit = true;
    o.projected_hessian = true;
    o.step_limit_m = 1e9;
    o.force_tolerance = 1e-6;
    twin::VecX y = x;
    const real_sheet::EquilibriumReport r = real_sheet::solve_equilibrium(model_, y, jaws, o, &terms, &workspace_);
    if (!r.converged && !r.budget_used) return r.message;
    if (!y.allFinite()) return "the step gave non-finite positions";
    v = (y - x) / dt_s;
    x = y;
    return "";
  }

  bool clamps_compatible(const std::vector<twin::ClampSpec>& specs) const override {
    for (std::size_t a = 0; a < specs.size(); ++a) {
      for (std::size_t b = a + 1; b < specs.size(); ++b) {
        const double gap = (specs[a].material_point_m - specs[b].material_point_m).norm();
        if (gap < specs[a].grip_radius_m + specs[b].grip_radius_m + 1e-3) return false;  // pads would overlap
      }
    }
    return true;
  }

  Eigen::Isometry3d patch_pose(const twin::ClampSpec& spec, const twin::VecX& x) const override {
    const real_sheet::Grid& grid = model_.grid();
    const twin::Vec2 uv = spec.material_point_m;
    const real_sheet::Grid::Location at = grid.locate(uv);
    const auto p = [&](int k) { return twin::Vec3(x.segment<3>(3 * at.nodes[k])); };
    const twin::Vec3 n = model_.normal_at(x, uv);
    const twin::Vec3 xu = p(1) - p(0) + p(2) - p(3);
    const twin::Vec3 u = (xu - xu.dot(n) * n).normalized();
    Eigen::Isometry3d patch = Eigen::Isometry3d::Identity();
    patch.translation() = grid.position(x, at);
    patch.linear().col(0) = u;
    patch.linear().col(1) = n.cross(u);
    patch.linear().col(2) = n;
    return patch;
  }

 private:
  std::vector<real_sheet::JawHold> holds(const std::vector<twin::ClampSpec>& specs,
                                         const std::vector<twin::ClampPose>& poses) const {
    std::vector<real_sheet::JawHold> jaws;
    for (std::size_t k = 0; k < specs.size(); ++k) {
      if (!poses[k].engaged) continue;
      real_sheet::JawPadOptions o;
      o.grip_radius_m = specs[k].grip_radius_m;
      o.extension_m = model_.material().pad_extension_m;
      o.extension_strength = model_.material().pad_strength;
      o.slip_compliance_m_N = model_.material().slip_compliance_m_N;
      real_sheet::JawHold h;
      h.pad = real_sheet::make_jaw_pad(model_.grid(), specs[k].id, specs[k].material_point_m, real_sheet::JawKind::kRigid, o);
      h.centre_m = poses[k].position_m;
      h.rotation = poses[k].rotation;
      jaws.push_back(std::move(h));
    }
    return jaws;
  }

  real_sheet::SheetModel model_;
  twin::SheetMesh mesh_;
  real_sheet::SolveWorkspace workspace_;  // the steps' pattern and analysis, while the grips stay
};

}  // namespace

std::unique_ptr<TrueSheetPhysics> make_true_sheet_physics(const twin::SheetSpec& sheet, const twin::Material& material,
                                                          const TrueSheetOptions& options) {
  material.validate();
  if (options.model == TruthModel::kTwin) return std::make_unique<TwinPhysics>(sheet.mesh, material);
  // The independent plate needs a rectangle [0, W] x [0, H] of material coordinates.
  twin::Vec2 lo = twin::Vec2::Constant(1e300), hi = twin::Vec2::Constant(-1e300);
  for (const twin::Vec2& uv : sheet.mesh.rest_uv) {
    lo = lo.cwiseMin(uv);
    hi = hi.cwiseMax(uv);
  }
  const double area = sheet.mesh.total_rest_area(), box = (hi - lo).prod();
  if (sheet.mesh.rest_uv.empty() || lo.norm() > 1e-9 || std::abs(area - box) > 1e-6 * box) {
    throw std::invalid_argument(fmt::format(
        "true sheet: the independent model needs a rectangular sheet from material point (0, 0) (this one covers {:.4f} "
        "of its {:.4f} m^2 bounding box); set \"truth_model\": \"twin\" for other shapes", area, box));
  }
  if (!(options.grid_spacing_m > 0)) throw std::invalid_argument("true sheet: grid_spacing_m must be positive");
  return std::make_unique<IndependentPhysics>(hi.x(), hi.y(), material, options.grid_spacing_m);
}

}  // namespace sim_hw
