// Grasp-planning goals (cell/grasp_planning/grasp_goal.h, with the material and mesh files they
// name), as `plan_grasps` reads them, then the screening mesh it builds. The input holds the files
// (fuzz_support.h: "%%FILE name" lines).
#include "cell/grasp_planning/grasp_goal.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "goal.json", [](const std::string& path) {
    const cell::GraspGoal goal = cell::read_grasp_goal(path);
    (void)cell::screening_mesh(goal);
  });
  return 0;
}
