#include "drivers/v4l2_io.h"

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace drivers {

int LibcV4l2Io::open(const char* path, int flags) { return ::open(path, flags); }
int LibcV4l2Io::close(int fd) { return ::close(fd); }
int LibcV4l2Io::ioctl(int fd, unsigned long request, void* arg) { return ::ioctl(fd, request, arg); }
void* LibcV4l2Io::mmap(std::size_t length, int fd, off_t offset) {
  return ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset);
}
int LibcV4l2Io::munmap(void* address, std::size_t length) { return ::munmap(address, length); }
int LibcV4l2Io::poll(pollfd* fds, nfds_t count, int timeout_ms) { return ::poll(fds, count, timeout_ms); }

}  // namespace drivers
