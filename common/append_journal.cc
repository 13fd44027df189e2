#include "common/append_journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <string>

#include "common/durable_file.h"

namespace prepreg {

namespace fs = std::filesystem;

AppendJournal::AppendJournal(fs::path path)
    : path_(std::move(path)), fd_(::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0666)) {
  if (!fd_) {
    const int error = errno;  // before anything else can change it
    throw file_error(path_, "cannot create the file", error);
  }
  const fs::path parent = path_.parent_path();
  sync_directory(parent.empty() ? fs::path(".") : parent);
}

void AppendJournal::append(std::string_view record) {
  if (const int error = write_all(fd_.get(), record); error != 0) throw file_error(path_, "write failed", error);
  if (::fdatasync(fd_.get()) != 0) {
    const int error = errno;
    throw file_error(path_, "cannot flush to the disk", error);
  }
}

}  // namespace prepreg
