// Grasp-planning goals (cell/grasp_planning/grasp_goal.h, with the material and mesh files they
// name), as `plan_grasps` reads them, then the screening mesh it builds. The input holds the files
// (fuzz_support.h: "%%FILE name" lines).
#include "cell/grasp_planning/grasp_goal.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::write_scratch_files(data, size, "goal.json");
  const std::string dir = fuzz::scratch_dir().string();
  const std::string path = (fuzz::scratch_dir() / "goal.json").string();
  fuzz::read_or_named_error(dir, [&] {
    const cell::GraspGoal goal = cell::read_grasp_goal(path);
    (void)cell::screening_mesh(goal);
  });
  return 0;
}
