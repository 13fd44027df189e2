#include "sim_hw/emulated_v4l2_node.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <new>
#include <stdexcept>

namespace sim_hw {
namespace {

void copy_text(char* dst, std::size_t size, const std::string& text) {
  std::memset(dst, 0, size);
  std::memcpy(dst, text.data(), std::min(size - 1, text.size()));
}

}  // namespace

std::int64_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
}

EmulatedV4l2Node EmulatedV4l2Node::create(const std::string& name, std::uint32_t pixel_format, int width,
                                          int height, int fps) {
  if (width <= 0 || height <= 0 || width % 2 != 0 || fps <= 0)
    throw std::invalid_argument("emulated V4L2 node " + name + ": bad mode " + std::to_string(width) + "x" +
                                std::to_string(height) + "@" + std::to_string(fps) + " (width even, > 0)");
  const std::string path = v4l2_shm::shm_path(name);
  ::shm_unlink(path.c_str());  // a leftover of a crashed run
  const int fd = ::shm_open(path.c_str(), O_RDWR | O_CREAT | O_EXCL, 0600);
  if (fd < 0) throw std::runtime_error("shm_open " + path + ": " + std::strerror(errno));
  const std::uint32_t frame_bytes = static_cast<std::uint32_t>(width) * height * 2;
  const std::uint32_t stride = static_cast<std::uint32_t>((v4l2_shm::kSlotHeaderBytes + frame_bytes + 63) / 64 * 64);
  const std::size_t bytes = v4l2_shm::total_bytes(stride, v4l2_shm::kSlotCount);
  void* addr = MAP_FAILED;
  struct stat st {};
  if (::ftruncate(fd, static_cast<off_t>(bytes)) == 0 && ::fstat(fd, &st) == 0)
    addr = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int err = errno;
  ::close(fd);
  if (addr == MAP_FAILED) {
    ::shm_unlink(path.c_str());
    throw std::runtime_error("creating emulated V4L2 node " + path + ": " + std::strerror(err));
  }
  // The fresh object is zero-filled: construct the atomics in place, then fill the fields.
  auto* h = new (addr) v4l2_shm::Header{};
  h->version = v4l2_shm::kVersion;
  h->pixel_format = pixel_format;
  h->width = static_cast<std::uint32_t>(width);
  h->height = static_cast<std::uint32_t>(height);
  h->bytes_per_line = static_cast<std::uint32_t>(width) * 2;
  h->frame_bytes = frame_bytes;
  h->fps = static_cast<std::uint32_t>(fps);
  h->slot_count = v4l2_shm::kSlotCount;
  h->slot_stride = stride;
  copy_text(h->driver, sizeof h->driver, "uvcvideo");
  copy_text(h->card, sizeof h->card, "Intel(R) RealSense(TM) Depth Ca");  // 31 chars, as uvcvideo cuts it
  copy_text(h->bus_info, sizeof h->bus_info, "usb-prepreg-emulated-" + name);
  h->alive.store(1);
  h->published.store(0);
  for (std::uint32_t i = 0; i < v4l2_shm::kSlotCount; ++i) {
    auto* slot = reinterpret_cast<std::uint8_t*>(addr) + v4l2_shm::kHeaderBytes + std::size_t{i} * stride;
    auto* s = new (slot) v4l2_shm::SlotHeader{};
    s->number = ~std::uint64_t{0};  // empty
  }
  h->magic.store(v4l2_shm::kMagic, std::memory_order_release);
  EmulatedV4l2Node node;
  node.name_ = name;
  node.map_ = {h, bytes};
  node.device_ = st.st_dev;
  node.inode_ = st.st_ino;
  return node;
}

EmulatedV4l2Node::EmulatedV4l2Node(EmulatedV4l2Node&& other) noexcept
    : name_(std::move(other.name_)), map_(other.map_), device_(other.device_), inode_(other.inode_) {
  other.map_ = {};
}

EmulatedV4l2Node& EmulatedV4l2Node::operator=(EmulatedV4l2Node&& other) noexcept {
  if (this != &other) {
    destroy();
    name_ = std::move(other.name_);
    map_ = other.map_;
    device_ = other.device_;
    inode_ = other.inode_;
    other.map_ = {};
  }
  return *this;
}

void EmulatedV4l2Node::publish(const std::uint8_t* data, std::size_t bytes, std::uint64_t sequence,
                               std::int64_t timestamp_us) {
  if (map_.header) v4l2_shm::write_frame(*map_.header, data, bytes, sequence, timestamp_us);
}

void EmulatedV4l2Node::mark_dead() {
  if (map_.header) map_.header->alive.store(0, std::memory_order_release);
}

void EmulatedV4l2Node::destroy() {
  if (!map_.header) return;
  mark_dead();
  const std::string path = v4l2_shm::shm_path(name_);
  const int fd = ::shm_open(path.c_str(), O_RDONLY, 0);
  if (fd >= 0) {
    struct stat st {};
    if (::fstat(fd, &st) == 0 && st.st_dev == device_ && st.st_ino == inode_) ::shm_unlink(path.c_str());
    ::close(fd);
  }
  ::munmap(map_.header, map_.bytes);
  map_ = {};
}

}  // namespace sim_hw
