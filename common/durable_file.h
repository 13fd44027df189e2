#pragma once
// Every result a user keeps (trials, materials, reports, camera sessions and frames, batch state)
// is written through here. The body goes to "<path>.tmp", which is flushed to the disk (fsync)
// before it is renamed over `path`, and the directory is flushed after the rename. After a
// crash or a power cut `path` therefore holds the old file or the whole new one, never an empty
// or half-written one; a failed write leaves the old file as it was.
// Shared by twin/, drivers/, tracking/, sim_hw/ and cell/, so it depends on nothing but the
// standard library and POSIX. Errors throw std::runtime_error naming the path and the reason.

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace prepreg {

// The stream is in the classic locale with max_digits10 precision for doubles.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& body);
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Flushes a directory's entries (files created, renamed or removed in it) to the disk.
void sync_directory(const std::filesystem::path& dir);

// std::filesystem::create_directories, then flushes the parent of every directory it created,
// so that a new directory survives a crash along with the files later written into it.
void create_directories_durably(const std::filesystem::path& dir);

}  // namespace prepreg
