#include "common/file_descriptor.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace prepreg {

FileDescriptor& FileDescriptor::operator=(FileDescriptor&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

int FileDescriptor::close() {
  if (fd_ < 0) return 0;
  const int result = ::close(fd_);
  fd_ = -1;
  // After EINTR Linux has closed the descriptor already; retrying could close another file's.
  return result == 0 || errno == EINTR ? 0 : errno;
}

int write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return 0;
}

std::runtime_error file_error(const std::filesystem::path& path, const std::string& what, int error) {
  return std::runtime_error(path.string() + ": " + what + ": " + std::strerror(error));
}

}  // namespace prepreg
