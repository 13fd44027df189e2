#pragma once
// The physics behind the fake world's true sheet (true_sheet.h), one of two models:
//   independent (the default): sim_hw/real_sheet, physics that shares no mesh, energy or solver
//     code with the twin (issue 33), on a uniform grid, linearised backward Euler;
//   twin: the twin's own shell model (the world before issue 33: a cell scored against itself).
// TrueSheet owns the threads and the grips; a physics model only solves. Not thread-safe.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim_hw/lab_reference.h"
#include "twin/model/clamp.h"
#include "twin/model/material.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/trials/sheet_spec.h"

namespace sim_hw {

struct TrueSheetOptions {
  TruthModel model = TruthModel::kIndependent;
  // Independent model: a uniform grid as coarse as the world's real-time step needs (about the
  // resolution the twin's 2000-triangle true sheet had before).
  double grid_spacing_m = 0.04;
};

class TrueSheetPhysics {
 public:
  virtual ~TrueSheetPhysics() = default;
  // The surface the cameras see and SIM_SHEET_TRUTH carries: vertices in material coordinates
  // and triangles; positions are stacked 3n (m) in its vertex order.
  virtual const twin::SheetMesh& mesh() const = 0;
  // Static equilibrium from x with the clamps' patches held at `poses` (clamps in `specs`
  // order). failure is "" on success (x updated) or why it failed (x unchanged).
  struct Settled {
    std::string failure;
    int iterations = 0;
  };
  virtual Settled settle(const std::vector<twin::ClampSpec>& specs, const std::vector<twin::ClampPose>& poses,
                         twin::VecX& x) = 0;
  // One step of dt with the clamps at `poses`; `specs_changed` when the set of clamps is new.
  // Returns "" on success (x, v updated) or why it failed (x, v unchanged).
  virtual std::string step(const std::vector<twin::ClampSpec>& specs, const std::vector<twin::ClampPose>& poses,
                           bool specs_changed, double dt_s, twin::VecX& x, twin::VecX& v) = 0;
  // Whether these clamps can hold together (no two on one patch); a clamp on a material point.
  virtual bool clamps_compatible(const std::vector<twin::ClampSpec>& specs) const = 0;
  // Where a clamp's patch is at x: material point position and frame (columns u, v, normal).
  virtual Eigen::Isometry3d patch_pose(const twin::ClampSpec& spec, const twin::VecX& x) const = 0;
  virtual int last_substeps() const { return 1; }
};

// Throws std::invalid_argument for a sheet the model cannot take (the independent model needs a
// rectangle) or an invalid material.
std::unique_ptr<TrueSheetPhysics> make_true_sheet_physics(const twin::SheetSpec& sheet, const twin::Material& material,
                                                          const TrueSheetOptions& options);

}  // namespace sim_hw
