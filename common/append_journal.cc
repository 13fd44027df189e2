#include "common/append_journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

#include "common/durable_file.h"

namespace prepreg {

namespace fs = std::filesystem;

namespace {

std::runtime_error failure(const fs::path& path, const std::string& what, int error) {
  return std::runtime_error(path.string() + ": " + what + ": " + std::strerror(error));
}

}  // namespace

AppendJournal::AppendJournal(fs::path path)
    : path_(std::move(path)), fd_(::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0666)) {
  if (!fd_) throw failure(path_, "cannot create the file", errno);
  const fs::path parent = path_.parent_path();
  sync_directory(parent.empty() ? fs::path(".") : parent);
}

void AppendJournal::append(std::string_view record) {
  if (const int error = write_all(fd_.get(), record); error != 0) throw failure(path_, "write failed", error);
  if (::fdatasync(fd_.get()) != 0) throw failure(path_, "cannot flush to the disk", errno);
}

}  // namespace prepreg
