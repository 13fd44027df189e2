// libprepreg_v4l2_shim.so: a user-space V4L2 device emulation loaded with LD_PRELOAD, so the real
// V4L2 back-end (drivers/v4l2_*) runs unchanged on a machine without /dev/video (CI).
//
//   export PREPREG_V4L2_EMULATION="/dev/video0=prepreg_cam0_depth,/dev/video2=prepreg_cam0_color"
//   LD_PRELOAD=.../libprepreg_v4l2_shim.so camera_probe --config cell.json
//
// open/open64/openat/openat64 of a listed path attach an EmulatedV4l2Device to the producer's shm
// node (sim_hw/emulated_v4l2_node.h) and return a real, unique fd (an eventfd reserved for it);
// ioctl, mmap/mmap64, munmap, poll and close on such fds are served by the device model. Every
// other path, fd and address passes through to the next definition (libc), found with
// dlsym(RTLD_NEXT). Functions have C linkage and never let an exception out (errno ENOMEM).

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <sys/eventfd.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sim_hw/emulated_v4l2_device.h"

namespace {

using sim_hw::EmulatedV4l2Device;
using OpenFn = int (*)(const char*, int, ...);
using OpenatFn = int (*)(int, const char*, int, ...);
using CloseFn = int (*)(int);
using IoctlFn = int (*)(int, unsigned long, ...);
using MmapFn = void* (*)(void*, size_t, int, int, int, off_t);
using MunmapFn = int (*)(void*, size_t);
using PollFn = int (*)(struct pollfd*, nfds_t, int);

template <class F>
F next_symbol(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

struct Shim {
  OpenFn open = next_symbol<OpenFn>("open");
  OpenFn open64 = next_symbol<OpenFn>("open64");
  OpenatFn openat = next_symbol<OpenatFn>("openat");
  OpenatFn openat64 = next_symbol<OpenatFn>("openat64");
  CloseFn close = next_symbol<CloseFn>("close");
  IoctlFn ioctl = next_symbol<IoctlFn>("ioctl");
  MmapFn mmap = next_symbol<MmapFn>("mmap");
  MmapFn mmap64 = next_symbol<MmapFn>("mmap64");
  MunmapFn munmap = next_symbol<MunmapFn>("munmap");
  PollFn poll = next_symbol<PollFn>("poll");

  std::map<std::string, std::string> shm_by_path;  // device path -> shm node name; read-only
  std::mutex mutex;
  std::map<int, std::shared_ptr<EmulatedV4l2Device>> devices;  // by fd
  std::vector<std::shared_ptr<EmulatedV4l2Device>> closed_but_mapped;  // as the kernel keeps them

  Shim() {
    const char* env = std::getenv("PREPREG_V4L2_EMULATION");
    std::string spec = env ? env : "";
    std::size_t pos = 0;
    while (pos < spec.size()) {
      const std::size_t comma = std::min(spec.find(',', pos), spec.size());
      const std::string item = spec.substr(pos, comma - pos);
      const std::size_t eq = item.find('=');
      if (eq != std::string::npos && eq > 0 && eq + 1 < item.size())
        shm_by_path[item.substr(0, eq)] = item.substr(eq + 1);
      pos = comma + 1;
    }
  }
};

// Built on first use and never destroyed: interposed calls can come during exit.
Shim& shim() {
  static Shim* instance = new Shim;
  return *instance;
}

__attribute__((constructor)) void init_shim() { shim(); }

std::shared_ptr<EmulatedV4l2Device> device_of(int fd) {
  if (fd < 0) return nullptr;
  Shim& s = shim();
  std::lock_guard lock(s.mutex);
  auto it = s.devices.find(fd);
  return it == s.devices.end() ? nullptr : it->second;
}

// -2: not an emulated path; otherwise the fd or -1 with errno.
int open_emulated(const char* path, int flags) {
  if (!path) return -2;
  Shim& s = shim();
  auto it = s.shm_by_path.find(path);
  if (it == s.shm_by_path.end()) return -2;
  try {
    auto device = std::make_shared<EmulatedV4l2Device>();
    const int r = device->open(it->second, (flags & O_NONBLOCK) != 0);
    if (r < 0) {
      errno = -r;
      return -1;
    }
    const int fd = eventfd(0, (flags & O_CLOEXEC) ? EFD_CLOEXEC : 0);
    if (fd < 0) return -1;
    std::lock_guard lock(s.mutex);
    s.devices[fd] = std::move(device);
    return fd;
  } catch (...) {
    errno = ENOMEM;
    return -1;
  }
}

mode_t mode_arg(int flags, va_list args) {
  return (flags & (O_CREAT | O_TMPFILE)) ? static_cast<mode_t>(va_arg(args, int)) : 0;
}

void* map_emulated(const std::shared_ptr<EmulatedV4l2Device>& device, size_t length, off_t offset) {
  void* p = device->map(length, static_cast<std::uint64_t>(offset));
  return p ? p : MAP_FAILED;
}

}  // namespace

extern "C" {

int open(const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_arg(flags, args);
  va_end(args);
  const int r = open_emulated(path, flags);
  return r != -2 ? r : shim().open(path, flags, mode);
}

int open64(const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_arg(flags, args);
  va_end(args);
  const int r = open_emulated(path, flags);
  return r != -2 ? r : shim().open64(path, flags, mode);
}

int openat(int dir_fd, const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_arg(flags, args);
  va_end(args);
  const int r = (path[0] == '/') ? open_emulated(path, flags) : -2;
  return r != -2 ? r : shim().openat(dir_fd, path, flags, mode);
}

int openat64(int dir_fd, const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_arg(flags, args);
  va_end(args);
  const int r = (path[0] == '/') ? open_emulated(path, flags) : -2;
  return r != -2 ? r : shim().openat64(dir_fd, path, flags, mode);
}

int close(int fd) {
  if (fd >= 0) {
    Shim& s = shim();
    std::lock_guard lock(s.mutex);
    auto it = s.devices.find(fd);
    if (it != s.devices.end()) {
      try {
        if (it->second->has_mapped_buffers()) s.closed_but_mapped.push_back(it->second);
      } catch (...) {
      }
      s.devices.erase(it);
    }
  }
  return shim().close(fd);  // the reserved eventfd, or any other fd
}

int ioctl(int fd, unsigned long request, ...) noexcept {
  va_list args;
  va_start(args, request);
  void* arg = va_arg(args, void*);
  va_end(args);
  if (auto device = device_of(fd)) {
    const int r = device->ioctl(request, arg);
    if (r < 0) {
      errno = -r;
      return -1;
    }
    return r;
  }
  return shim().ioctl(fd, request, arg);
}

void* mmap(void* address, size_t length, int prot, int flags, int fd, off_t offset) noexcept {
  if (fd >= 0)
    if (auto device = device_of(fd)) return map_emulated(device, length, offset);
  MmapFn real = shim().mmap;
  return real ? real(address, length, prot, flags, fd, offset)
              : reinterpret_cast<void*>(syscall(SYS_mmap, address, length, prot, flags, fd, offset));
}

void* mmap64(void* address, size_t length, int prot, int flags, int fd, off64_t offset) noexcept {
  if (fd >= 0)
    if (auto device = device_of(fd)) return map_emulated(device, length, offset);
  MmapFn real = shim().mmap64;
  return real ? real(address, length, prot, flags, fd, offset)
              : reinterpret_cast<void*>(syscall(SYS_mmap, address, length, prot, flags, fd, offset));
}

int munmap(void* address, size_t length) noexcept {
  {
    Shim& s = shim();
    std::lock_guard lock(s.mutex);
    for (auto& [fd, device] : s.devices)
      if (device->unmap(address)) return 0;
    for (std::size_t i = 0; i < s.closed_but_mapped.size(); ++i) {
      if (s.closed_but_mapped[i]->unmap(address)) {
        if (!s.closed_but_mapped[i]->has_mapped_buffers())
          s.closed_but_mapped.erase(s.closed_but_mapped.begin() + static_cast<std::ptrdiff_t>(i));
        return 0;
      }
    }
  }
  return shim().munmap(address, length);
}

int poll(struct pollfd* fds, nfds_t count, int timeout_ms) {
  std::vector<std::shared_ptr<EmulatedV4l2Device>> devices(count);
  bool any = false;
  try {
    for (nfds_t i = 0; i < count; ++i) any |= (devices[i] = device_of(fds[i].fd)) != nullptr;
  } catch (...) {
    errno = ENOMEM;
    return -1;
  }
  if (!any) return shim().poll(fds, count, timeout_ms);
  // Emulated fds have no kernel wait queue: check all fds every millisecond until the timeout.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    int ready = 0;
    for (nfds_t i = 0; i < count; ++i) {
      fds[i].revents = 0;
      if (devices[i]) {
        fds[i].revents = devices[i]->poll_events(fds[i].events);
      } else if (fds[i].fd >= 0) {
        if (shim().poll(&fds[i], 1, 0) < 0) return -1;
      }
      ready += fds[i].revents != 0;
    }
    if (ready > 0 || timeout_ms == 0 || (timeout_ms > 0 && std::chrono::steady_clock::now() >= deadline))
      return ready;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // extern "C"
