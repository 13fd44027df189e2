#include "sim_hw/emulated_v4l2_io.h"

#include <fcntl.h>
#include <sys/mman.h>

#include <cerrno>
#include <chrono>
#include <thread>

namespace sim_hw {

EmulatedV4l2Io::EmulatedV4l2Io(std::map<std::string, std::string> shm_by_path)
    : shm_by_path_(std::move(shm_by_path)) {}

std::shared_ptr<EmulatedV4l2Device> EmulatedV4l2Io::device(int fd) const {
  std::lock_guard lock(mutex_);
  auto it = devices_.find(fd);
  return it == devices_.end() ? nullptr : it->second;
}

int EmulatedV4l2Io::open(const char* path, int flags) {
  auto it = shm_by_path_.find(path);
  if (it == shm_by_path_.end()) {
    errno = ENOENT;
    return -1;
  }
  auto dev = std::make_shared<EmulatedV4l2Device>();
  const int r = dev->open(it->second, (flags & O_NONBLOCK) != 0);
  if (r < 0) {
    errno = -r;
    return -1;
  }
  std::lock_guard lock(mutex_);
  devices_[next_fd_] = std::move(dev);
  return next_fd_++;
}

int EmulatedV4l2Io::close(int fd) {
  std::lock_guard lock(mutex_);
  if (devices_.erase(fd) == 0) {
    errno = EBADF;
    return -1;
  }
  return 0;
}

int EmulatedV4l2Io::ioctl(int fd, unsigned long request, void* arg) {
  auto dev = device(fd);
  if (!dev) {
    errno = EBADF;
    return -1;
  }
  const int r = dev->ioctl(request, arg);
  if (r < 0) {
    errno = -r;
    return -1;
  }
  return r;
}

void* EmulatedV4l2Io::mmap(std::size_t length, int fd, off_t offset) {
  auto dev = device(fd);
  if (!dev) {
    errno = EBADF;
    return MAP_FAILED;
  }
  void* p = dev->map(length, static_cast<std::uint64_t>(offset));
  return p ? p : MAP_FAILED;
}

int EmulatedV4l2Io::munmap(void* address, std::size_t) {
  std::lock_guard lock(mutex_);
  for (auto& [fd, dev] : devices_)
    if (dev->unmap(address)) return 0;
  errno = EINVAL;
  return -1;
}

int EmulatedV4l2Io::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    int ready = 0;
    for (nfds_t i = 0; i < count; ++i) {
      auto dev = device(fds[i].fd);
      fds[i].revents = dev ? dev->poll_events(fds[i].events) : POLLNVAL;
      ready += fds[i].revents != 0;
    }
    if (ready > 0 || timeout_ms == 0 || (timeout_ms > 0 && std::chrono::steady_clock::now() >= deadline))
      return ready;  // a negative timeout waits for ever, as poll(2)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

int EmulatedV4l2Io::open_fds() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(devices_.size());
}

}  // namespace sim_hw
