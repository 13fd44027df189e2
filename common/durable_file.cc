#include "common/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <iomanip>
#include <limits>
#include <locale>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

#include "common/file_descriptor.h"

namespace prepreg {

namespace fs = std::filesystem;

namespace {

// A std::ostream's buffer over a file descriptor, so that the body streams straight to the file
// (clouds and frames can be large) and the descriptor stays at hand for fsync.
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd), buffer_(1 << 16) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  // errno of the first failed write, 0 when none failed.
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    if (error_ != 0) return false;
    error_ = write_all(fd_, std::string_view(pbase(), static_cast<std::size_t>(pptr() - pbase())));
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return error_ == 0;
  }

  int fd_;
  std::vector<char> buffer_;
  int error_ = 0;
};

fs::path directory_of(const fs::path& path) {
  const fs::path parent = path.parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

}  // namespace

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& body) {
  fs::path tmp = path;
  tmp += ".tmp";
  FileDescriptor fd(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666));
  if (!fd) {
    const int error = errno;  // before building the message can change it
    throw file_error(path, "cannot open " + tmp.string() + " for writing", error);
  }
  std::error_code ignored;
  // Until the rename the old file is untouched; every failure below only removes the temporary.
  auto give_up = [&] { fd.close(); fs::remove(tmp, ignored); };
  try {
    DescriptorBuffer buffer(fd.get());
    std::ostream out(&buffer);
    out.imbue(std::locale::classic());
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    body(out);
    out.flush();
    if (buffer.error() != 0) throw file_error(path, "writing " + tmp.string() + " failed", buffer.error());
    if (!out) throw std::runtime_error(path.string() + ": writing " + tmp.string() + " failed");
  } catch (...) {
    give_up();
    throw;
  }
  if (::fsync(fd.get()) != 0) {
    const int error = errno;
    give_up();
    throw file_error(path, "cannot flush " + tmp.string() + " to the disk", error);
  }
  if (const int error = fd.close(); error != 0) {
    fs::remove(tmp, ignored);
    throw file_error(path, "closing " + tmp.string() + " failed", error);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    fs::remove(tmp, ignored);
    throw file_error(path, "cannot rename " + tmp.string() + " over it", error);
  }
  sync_directory(directory_of(path));
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
  write_file_atomically(path, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

void sync_directory(const fs::path& dir) {
  FileDescriptor fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (!fd) {
    const int error = errno;
    throw file_error(dir, "cannot open the directory to flush it", error);
  }
  if (::fsync(fd.get()) != 0) {
    const int error = errno;
    throw file_error(dir, "cannot flush the directory to the disk", error);
  }
}

void create_directories_durably(const fs::path& dir) {
  // The missing ancestors, outermost first: each one's parent is flushed once it exists.
  std::vector<fs::path> missing;
  for (fs::path p = dir; !p.empty() && !fs::exists(p); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create the directory: " + ec.message());
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) sync_directory(directory_of(*it));
}

}  // namespace prepreg
