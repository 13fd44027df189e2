#pragma once
// Small helpers shared by the trial reader (trial.cc) and writer (trial_writer.cc).

#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "twin/base/types.h"

namespace twin::trial_internal {

inline std::string describe_uv(const Vec2& uv_m) {
  return fmt::format("({:.6g}, {:.6g}) m", uv_m.x(), uv_m.y());
}

// A file named in trial.json: relative names are relative to the trial directory.
inline std::filesystem::path resolve(const std::filesystem::path& directory, const std::string& name) {
  const std::filesystem::path p(name);
  return p.is_absolute() ? p : directory / p;
}

}  // namespace twin::trial_internal
