#pragma once
// The settled states a cell saw (settled_state.h) as a scanned trial (twin/trials/trial.h), so
// that identification and diagnosis run on them exactly as on a lab's trials, offline
// (`twin identify --train DIR`, `twin diagnose`) or in the cell (in_situ_calibration.h).
//
// The trial directory:
//   trial.json         sheet = "sheet.obj" (the twin's own rest mesh: the material is then
//                      identified on the discretisation the cell runs), the material's
//                      thickness and surface density, one marker per twin vertex (its material
//                      point), the plan's grasps as clamps (id = gripper), one stage per state
//                      (clamp positions as measured, "released" for a gripper that let go)
//   sheet.obj          the rest mesh (x, y = u, v in m, z = 0)
//   s<k>.xyz           per stage, the tracked position of every vertex averaged over the settled
//                      window, "nan nan nan" where the cameras did not see it
//   observations.json  per stage: cycles averaged, coverage, the tracker's scatter per cycle and
//                      of the mean, drift, cycle ids (what a reader needs to weigh the stages),
//                      and truth_file (fake hardware, else null)
//   truth/s<k>.xyz     fake hardware only: the world's true sheet at the state, on the world's
//                      own mesh (SIM_SHEET_TRUTH's vertices; sim_hw truth_trial maps it onto the
//                      markers)
//
// What the trial format cannot carry: the jaws' orientation (a trial's clamps are level). A cell
// whose ply lies rotated in its placement holds it turned; its trial's stages are then solved
// with level jaws (cell_trial_problem says so).
#include <string>
#include <vector>

#include "cell/learning/settled_state.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/model/material.h"
#include "twin/trials/grasp_plan.h"
#include "twin/trials/trial.h"

namespace cell::learning {

// The trial of `states` (stage ids s1, s2, ... in their order). `mesh_file` is what the trial's
// sheet names (the rest mesh written beside it). Throws std::invalid_argument when there is no
// state or a state does not match the mesh or the plan.
twin::Trial cell_trial(const std::vector<SettledObservation>& states, const twin::SheetMesh& mesh,
                       const twin::GraspPlan& plan, const twin::Material& material, const std::string& mesh_file);

// Writes the trial directory described above into `directory` (created if needed; each file
// replaced atomically, trial.json last) and returns the trial as read_trial reads it back (so
// what the cell fits is what an offline run would read). Throws std::runtime_error naming the
// path when it cannot be written, std::invalid_argument as cell_trial.
twin::Trial write_cell_trial(const std::string& directory, const std::vector<SettledObservation>& states,
                             const twin::SheetMesh& mesh, const twin::GraspPlan& plan, const twin::Material& material);

// Anything about the trial the cell's own twin does differently (the jaws' orientation when the
// cell's placement is rotated); "" when nothing.
std::string cell_trial_problem(const twin::SheetPlacement& placement);

}  // namespace cell::learning
