// A cell's settled states as a trial directory (cell/learning/cell_trial.h): what is written reads
// back as the same trial, unseen vertices stay unseen, released grippers stay released.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "cell/learning/cell_trial.h"
#include "tests/cell/learning/independent_states.h"
#include "tests/support/temp_dir.h"
#include "twin/mesh/mesh_io.h"

using cell::learning::SettledObservation;

TEST_CASE("a cell trial is written as a trial directory that read_trial takes back unchanged") {
  const twin::Material truth = testing_support::lab_material(6000, 2500, 8e-4);
  auto data = testing_support::independent_states(truth, 200, 0.05, 0.0005);
  data.states[1].vertices_m[3] = twin::Vec3::Constant(std::nan(""));  // not seen
  data.states[3].engaged[0] = 0;                                       // A let go
  testing_support::TempDir dir("cell_trial");
  const twin::Trial t =
      cell::learning::write_cell_trial((dir / "trial").string(), data.states, data.twin_mesh, data.plan, truth);

  CHECK(std::filesystem::exists(dir / "trial" / "observations.json"));
  CHECK(t.material_name == "test sheet");
  REQUIRE(t.surface_density_kg_m2);
  CHECK(*t.surface_density_kg_m2 == 0.3);
  CHECK(t.thickness_m == 0.0003);
  // The sheet is the twin's own mesh, vertex for vertex; one marker per vertex.
  const twin::SheetMesh read_mesh = twin::trial_sheet_mesh(t, 1);
  CHECK(read_mesh.triangles == data.twin_mesh.triangles);
  REQUIRE(t.marker_uv_m.size() == data.twin_mesh.rest_uv.size());
  CHECK((t.marker_uv_m[5] - data.twin_mesh.rest_uv[5]).norm() < 1e-12);
  REQUIRE(t.clamps.size() == 3);
  CHECK(t.clamps[2].id == "C");
  REQUIRE(t.stages.size() == 4);
  CHECK(t.stages[0].id == "s1");
  CHECK_FALSE(t.stages[1].observed.markers_m[3].allFinite());
  CHECK((t.stages[1].observed.markers_m[4] - data.states[1].vertices_m[4]).norm() < 1e-12);
  CHECK((t.stages[1].poses[2].position_m - data.states[1].grasp_positions_m[2]).norm() < 1e-12);
  CHECK_FALSE(t.stages[3].poses[0].engaged);
  CHECK(t.stages[3].poses[1].engaged);
  REQUIRE(t.stages[2].time_s);
  CHECK(*t.stages[2].time_s == data.states[2].time_s);
}

TEST_CASE("a cell trial refuses states that do not match the twin's mesh or plan") {
  const twin::Material truth = testing_support::lab_material(6000, 2500, 8e-4);
  auto data = testing_support::independent_states(truth, 200, 0.05, 0.0005);
  CHECK_THROWS_WITH(cell::learning::cell_trial({}, data.twin_mesh, data.plan, truth, "sheet.obj"),
                    Catch::Contains("no settled state"));
  data.states[2].vertices_m.pop_back();
  CHECK_THROWS_WITH(cell::learning::cell_trial(data.states, data.twin_mesh, data.plan, truth, "sheet.obj"),
                    Catch::Contains("state 3"));
  twin::Material no_thickness = truth;
  no_thickness.thickness_m.reset();
  CHECK_THROWS_WITH(cell::learning::cell_trial({data.states[0]}, data.twin_mesh, data.plan, no_thickness, "s.obj"),
                    Catch::Contains("thickness_m"));
}
