#pragma once
// A file that grows one record at a time, each record on the disk (fdatasync) before append
// returns: the index of a recorded camera session, whose lines name frames already written
// durably, so that after a crash the index names only frames that are there. A crash can leave
// at most the last record torn (without its newline); its readers skip such a line.
// Errors throw std::runtime_error naming the file and the reason.

#include <filesystem>
#include <string_view>

#include "common/file_descriptor.h"

namespace prepreg {

class AppendJournal {
 public:
  // Creates the file (emptying one that is there) and flushes its directory, so that the file
  // itself survives a crash.
  explicit AppendJournal(std::filesystem::path path);

  // Appends `record` (the caller ends it with its newline) in one write and flushes it.
  void append(std::string_view record);

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  FileDescriptor fd_;
};

}  // namespace prepreg
