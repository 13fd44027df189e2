#pragma once
// Every file the twin writes (meshes, material files, summaries) goes through here: the body is
// written to "<path>.tmp" and renamed over `path`, so a reader never sees a half-written file
// and an existing file survives a failed write. Throws std::runtime_error naming the path.

#include <filesystem>
#include <functional>
#include <ostream>

namespace twin {

// The stream is in the classic locale with max_digits10 precision for doubles.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& body);

}  // namespace twin
