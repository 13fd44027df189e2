// Branch following (cell/learning/branch_following.h): the twin's equilibrium near a settled
// sheet the cameras saw, here the fake world's independent sheet.
#include <catch2/catch.hpp>

#include "cell/learning/branch_following.h"
#include "tests/cell/learning/independent_states.h"

TEST_CASE("the equilibrium found near an observed sheet is an equilibrium near it, from a state far from it") {
  const twin::Material truth = testing_support::lab_material(6000, 2500, 8e-4);
  const auto data = testing_support::independent_states(truth, 400, 0.03, 0.0005);
  const cell::learning::SettledObservation& seen = data.states[1];
  std::vector<twin::ClampPose> poses;
  for (std::size_t g = 0; g < seen.engaged.size(); ++g) {
    twin::ClampPose p;
    p.position_m = seen.grasp_positions_m[g];
    p.engaged = seen.engaged[g] != 0;
    poses.push_back(p);
  }
  // The twin "on another branch": its sheet still lying flat at the height of the grasps.
  twin::SheetPlacement flat;
  flat.origin_m = twin::Vec3(0.0, 0.0, 1.0);
  const twin::VecX far = twin::place_flat(data.twin_mesh, flat);
  std::vector<twin::Vec3> observed = seen.vertices_m;
  for (std::size_t i = 0; i < observed.size(); i += 3) observed[i] = twin::Vec3::Constant(std::nan(""));  // unseen
  const auto c = cell::learning::equilibrium_near_observation(data.twin_mesh, truth, data.plan.clamp_specs(), poses,
                                                             far, observed);
  INFO(c.problem);
  REQUIRE(c.problem.empty());
  REQUIRE(c.x.size() == far.size());
  CHECK(c.x.allFinite());
  CHECK(c.before_m > 0.03);               // a flat sheet is far from a hanging one
  CHECK(c.after_m < 0.2 * c.before_m);    // the equilibrium found is near what was seen
  CHECK(c.better(0.3));
  CHECK_FALSE(c.better(0.999));
  // Sizes that do not match the mesh are refused.
  CHECK_THROWS_AS(cell::learning::equilibrium_near_observation(data.twin_mesh, truth, data.plan.clamp_specs(), poses,
                                                               far.head(3), observed),
                  std::invalid_argument);
}
