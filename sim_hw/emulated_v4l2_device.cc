#include "sim_hw/emulated_v4l2_device.h"

#include <linux/videodev2.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

namespace sim_hw {
namespace {

constexpr std::uint32_t kMaxBuffers = 32;
constexpr std::uint64_t kPage = 4096;

void copy_text(std::uint8_t* dst, std::size_t size, const char* text) {
  std::memset(dst, 0, size);
  std::memcpy(dst, text, strnlen(text, size - 1));
}

}  // namespace

EmulatedV4l2Device::~EmulatedV4l2Device() { v4l2_shm::detach(map_); }

int EmulatedV4l2Device::open(const std::string& shm_name, bool non_blocking) {
  std::lock_guard lock(mutex_);
  non_blocking_ = non_blocking;
  return v4l2_shm::attach(shm_name, map_);
}

void EmulatedV4l2Device::set_non_blocking(bool non_blocking) {
  std::lock_guard lock(mutex_);
  non_blocking_ = non_blocking;
}

bool EmulatedV4l2Device::alive() const {
  return map_.header && map_.header->alive.load(std::memory_order_acquire) != 0;
}

void EmulatedV4l2Device::fill_format(void* arg) const {
  auto& pix = static_cast<v4l2_format*>(arg)->fmt.pix;
  const v4l2_shm::Header& h = *map_.header;
  std::memset(&pix, 0, sizeof pix);
  pix.width = h.width;
  pix.height = h.height;
  pix.pixelformat = h.pixel_format;
  pix.field = V4L2_FIELD_NONE;
  pix.bytesperline = h.bytes_per_line;
  pix.sizeimage = h.frame_bytes;
  pix.colorspace = h.pixel_format == V4L2_PIX_FMT_YUYV ? V4L2_COLORSPACE_SRGB : V4L2_COLORSPACE_RAW;
}

int EmulatedV4l2Device::ioctl(unsigned long request, void* arg) {
  if (request == VIDIOC_DQBUF) {
    // Blocking DQBUF sleeps without the lock, so other threads' ioctls are not held up.
    for (;;) {
      {
        std::lock_guard lock(mutex_);
        const int r = dequeue(arg);
        if (r != -EAGAIN || non_blocking_) return r;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  std::lock_guard lock(mutex_);
  if (!alive()) return -ENODEV;
  const v4l2_shm::Header& h = *map_.header;
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      std::memset(cap, 0, sizeof *cap);
      copy_text(cap->driver, sizeof cap->driver, h.driver);
      copy_text(cap->card, sizeof cap->card, h.card);
      copy_text(cap->bus_info, sizeof cap->bus_info, h.bus_info);
      cap->version = 0x060100;  // kernel 6.1, Debian 12's
      cap->device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING | V4L2_CAP_EXT_PIX_FORMAT;
      cap->capabilities = cap->device_caps | V4L2_CAP_META_CAPTURE | V4L2_CAP_DEVICE_CAPS;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* f = static_cast<v4l2_fmtdesc*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || f->index != 0) return -EINVAL;
      const std::uint32_t index = f->index, type = f->type;
      std::memset(f, 0, sizeof *f);
      f->index = index;
      f->type = type;
      f->pixelformat = h.pixel_format;
      copy_text(f->description, sizeof f->description,
                h.pixel_format == V4L2_PIX_FMT_Z16 ? "16-bit Depth" : "YUYV 4:2:2");
      return 0;
    }
    case VIDIOC_G_FMT:
    case VIDIOC_TRY_FMT:
    case VIDIOC_S_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
      if (request == VIDIOC_S_FMT && !buffers_.empty()) return -EBUSY;
      fill_format(arg);  // one format and size: whatever was asked is adjusted to it
      return 0;
    }
    case VIDIOC_G_PARM:
    case VIDIOC_S_PARM: {
      auto* p = static_cast<v4l2_streamparm*>(arg);
      if (p->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
      std::memset(&p->parm.capture, 0, sizeof p->parm.capture);
      p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
      p->parm.capture.timeperframe = {1, h.fps};  // one rate: requests are adjusted to it
      return 0;
    }
    case VIDIOC_REQBUFS: {
      auto* r = static_cast<v4l2_requestbuffers*>(arg);
      if (r->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || r->memory != V4L2_MEMORY_MMAP) return -EINVAL;
      if (streaming_) return -EBUSY;
      if (std::any_of(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.mapped; })) return -EBUSY;
      buffers_.clear();
      queue_.clear();
      if (r->count == 0) return 0;
      r->count = std::clamp<std::uint32_t>(r->count, 2, kMaxBuffers);
      const std::uint64_t stride = (h.frame_bytes + kPage - 1) / kPage * kPage;
      buffers_.resize(r->count);
      for (std::uint32_t i = 0; i < r->count; ++i) {
        buffers_[i].memory.assign(h.frame_bytes, 0);
        buffers_[i].offset = i * stride;
      }
      r->capabilities = V4L2_BUF_CAP_SUPPORTS_MMAP;
      return 0;
    }
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->index >= buffers_.size() || b->memory != V4L2_MEMORY_MMAP)
        return -EINVAL;
      Buffer& buf = buffers_[b->index];
      if (request == VIDIOC_QBUF) {
        if (buf.queued) return -EINVAL;
        buf.queued = true;
        queue_.push_back(b->index);
      }
      b->length = h.frame_bytes;
      b->m.offset = static_cast<std::uint32_t>(buf.offset);
      b->flags = (buf.mapped ? V4L2_BUF_FLAG_MAPPED : 0) | (buf.queued ? V4L2_BUF_FLAG_QUEUED : 0) |
                 V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
      return 0;
    }
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF: {
      if (*static_cast<const int*>(arg) != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
      if (request == VIDIOC_STREAMON) {
        if (buffers_.empty()) return -EINVAL;
        if (!streaming_) next_number_ = h.published.load(std::memory_order_acquire);  // frames from now on
        streaming_ = true;
      } else {
        streaming_ = false;
        queue_.clear();  // every buffer returns to the application
        for (Buffer& b : buffers_) b.queued = false;
      }
      return 0;
    }
    default:
      return -ENOTTY;
  }
}

bool EmulatedV4l2Device::frame_ready() {
  return streaming_ && !queue_.empty() && next_number_ < map_.header->published.load(std::memory_order_acquire);
}

int EmulatedV4l2Device::dequeue(void* arg) {
  if (!alive()) return -ENODEV;
  auto* b = static_cast<v4l2_buffer*>(arg);
  if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP || !streaming_) return -EINVAL;
  const v4l2_shm::Header& h = *map_.header;
  while (frame_ready()) {
    // A real queue holds at most one frame per buffer; anything older was never captured.
    const std::uint64_t published = h.published.load(std::memory_order_acquire);
    const std::uint64_t backlog = std::min<std::uint64_t>(buffers_.size(), h.slot_count - 1);
    next_number_ = std::max(next_number_, published - std::min(published, backlog));
    const std::uint32_t index = queue_.front();
    Buffer& buf = buffers_[index];
    v4l2_shm::FrameInfo info;
    const bool got = v4l2_shm::read_frame(h, next_number_++, buf.memory.data(), buf.memory.size(), info);
    if (!got) continue;  // overwritten while we looked: take the next
    queue_.pop_front();
    buf.queued = false;
    std::memset(b, 0, sizeof *b);
    b->index = index;
    b->type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b->memory = V4L2_MEMORY_MMAP;
    b->bytesused = info.bytes_used;
    b->length = h.frame_bytes;
    b->m.offset = static_cast<std::uint32_t>(buf.offset);
    b->field = V4L2_FIELD_NONE;
    b->flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE | (buf.mapped ? V4L2_BUF_FLAG_MAPPED : 0);
    b->sequence = static_cast<std::uint32_t>(info.sequence);
    b->timestamp.tv_sec = info.timestamp_us / 1000000;
    b->timestamp.tv_usec = info.timestamp_us % 1000000;
    return 0;
  }
  return -EAGAIN;
}

void* EmulatedV4l2Device::map(std::size_t length, std::uint64_t offset) {
  std::lock_guard lock(mutex_);
  for (Buffer& b : buffers_) {
    if (b.offset == offset && length <= b.memory.size()) {
      b.mapped = true;
      return b.memory.data();
    }
  }
  errno = EINVAL;
  return nullptr;
}

bool EmulatedV4l2Device::unmap(const void* address) {
  std::lock_guard lock(mutex_);
  for (Buffer& b : buffers_) {
    if (b.mapped && b.memory.data() == address) {
      b.mapped = false;
      return true;
    }
  }
  return false;
}

bool EmulatedV4l2Device::has_mapped_buffers() const {
  std::lock_guard lock(mutex_);
  return std::any_of(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.mapped; });
}

short EmulatedV4l2Device::poll_events(short events) {
  std::lock_guard lock(mutex_);
  if (!alive() || !streaming_) return POLLERR;
  return frame_ready() ? static_cast<short>(events & (POLLIN | POLLRDNORM)) : 0;
}

}  // namespace sim_hw
