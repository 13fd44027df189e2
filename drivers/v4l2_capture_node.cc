#include "drivers/v4l2_capture_node.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <limits>
#include <optional>

namespace drivers {
namespace {

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A buffer's timestamp in microseconds, or nothing when the driver's timeval is out of range
// (negative, microseconds beyond a second, or too large for microseconds in 64 bits).
std::optional<std::int64_t> timestamp_us(const timeval& t) {
  constexpr std::int64_t kMaxSeconds = std::numeric_limits<std::int64_t>::max() / 1000000 - 1;
  if (t.tv_sec < 0 || t.tv_sec > kMaxSeconds || t.tv_usec < 0 || t.tv_usec >= 1000000) return std::nullopt;
  return static_cast<std::int64_t>(t.tv_sec) * 1000000 + t.tv_usec;
}

}  // namespace

std::string fourcc_text(std::uint32_t f) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((f >> (8 * i)) & 0xff);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

int V4l2CaptureNode::xioctl(unsigned long request, void* arg) {
  int r;
  do {
    r = io_.ioctl(fd_, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

DriverResult V4l2CaptureNode::fail(const char* what, int err) {
  error_ = spec_.path + ": " + what + ": " + std::strerror(err);
  return DriverResult::failure(error_);
}

DriverResult V4l2CaptureNode::open(const V4l2StreamSpec& spec) {
  close();
  spec_ = spec;
  // Non-blocking, so DQBUF never blocks: waiting is poll()'s job, with the read timeout.
  fd_ = io_.open(spec.path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) return fail("open", errno);

  v4l2_capability cap{};
  if (xioctl(VIDIOC_QUERYCAP, &cap) < 0) return fail("VIDIOC_QUERYCAP", errno);
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    error_ = spec.path + ": VIDIOC_QUERYCAP: " + reinterpret_cast<const char*>(cap.card) +
             " is not a streaming video-capture node (is this the metadata node?)";
    return DriverResult::failure(error_);
  }

  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.pixelformat = spec.pixel_format;
  fmt.fmt.pix.width = static_cast<std::uint32_t>(spec.width);
  fmt.fmt.pix.height = static_cast<std::uint32_t>(spec.height);
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(VIDIOC_S_FMT, &fmt) < 0) return fail("VIDIOC_S_FMT", errno);
  // A driver adjusts what it cannot do instead of failing; accept only the exact mode.
  if (fmt.fmt.pix.pixelformat != spec.pixel_format || fmt.fmt.pix.width != static_cast<std::uint32_t>(spec.width) ||
      fmt.fmt.pix.height != static_cast<std::uint32_t>(spec.height)) {
    error_ = spec.path + ": VIDIOC_S_FMT: device offers " + fourcc_text(fmt.fmt.pix.pixelformat) + " " +
             std::to_string(fmt.fmt.pix.width) + "x" + std::to_string(fmt.fmt.pix.height) +
             ", configured " + fourcc_text(spec.pixel_format) + " " + std::to_string(spec.width) + "x" +
             std::to_string(spec.height);
    return DriverResult::failure(error_);
  }
  bytes_per_line_ = std::max<std::uint32_t>(fmt.fmt.pix.bytesperline,
                                            static_cast<std::uint32_t>(spec.width * spec.bytes_per_pixel));

  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe.numerator = 1;
  parm.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(spec.fps);
  if (xioctl(VIDIOC_S_PARM, &parm) < 0) return fail("VIDIOC_S_PARM", errno);
  const v4l2_fract tpf = parm.parm.capture.timeperframe;
  if ((parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) && tpf.numerator != 0 &&
      tpf.denominator != static_cast<std::uint32_t>(spec.fps) * tpf.numerator) {
    error_ = spec.path + ": VIDIOC_S_PARM: device runs at " + std::to_string(tpf.denominator) + "/" +
             std::to_string(tpf.numerator) + " fps, configured " + std::to_string(spec.fps);
    return DriverResult::failure(error_);
  }

  v4l2_requestbuffers req{};
  req.count = kBufferCount;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(VIDIOC_REQBUFS, &req) < 0) return fail("VIDIOC_REQBUFS", errno);
  if (req.count < 2) {
    error_ = spec.path + ": VIDIOC_REQBUFS: only " + std::to_string(req.count) + " buffer(s) granted";
    return DriverResult::failure(error_);
  }
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(VIDIOC_QUERYBUF, &buf) < 0) return fail("VIDIOC_QUERYBUF", errno);
    void* start = io_.mmap(buf.length, fd_, static_cast<off_t>(buf.m.offset));
    if (start == MAP_FAILED) return fail("mmap", errno);
    buffers_.push_back({start, buf.length});
  }
  error_.clear();
  return DriverResult::success();
}

DriverResult V4l2CaptureNode::start() {
  if (fd_ < 0) return DriverResult::failure(spec_.path + ": not open");
  for (std::uint32_t i = 0; i < buffers_.size(); ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(VIDIOC_QBUF, &buf) < 0) return fail("VIDIOC_QBUF", errno);
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(VIDIOC_STREAMON, &type) < 0) return fail("VIDIOC_STREAMON", errno);
  streaming_ = true;
  return DriverResult::success();
}

bool V4l2CaptureNode::copy_out(std::uint32_t index, std::uint32_t bytes_used, CapturedImage& out) {
  if (index >= buffers_.size()) return false;
  const Buffer& b = buffers_[index];
  const std::size_t row = static_cast<std::size_t>(spec_.width) * spec_.bytes_per_pixel;
  const std::size_t available = std::min<std::size_t>(bytes_used, b.length);
  // A short buffer yields fewer rows; the frame checks then reject the size.
  const std::size_t rows = std::min<std::size_t>(spec_.height, available / bytes_per_line_ +
                                                 (available % bytes_per_line_ >= row ? 1 : 0));
  out.data.resize(rows * row);
  const auto* src = static_cast<const std::uint8_t*>(b.start);
  for (std::size_t y = 0; y < rows; ++y) std::memcpy(out.data.data() + y * row, src + y * bytes_per_line_, row);
  return true;
}

CaptureStatus V4l2CaptureNode::next(int timeout_ms, CapturedImage& out) {
  if (fd_ < 0 || !streaming_) {
    error_ = spec_.path + ": not streaming";
    return CaptureStatus::kLost;
  }
  const std::int64_t deadline = now_ms() + timeout_ms;
  bool poll_error = false;
  for (;;) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    if (xioctl(VIDIOC_DQBUF, &buf) == 0) {
      const bool ok = copy_out(buf.index, buf.bytesused, out);
      out.sequence = buf.sequence;
      const std::optional<std::int64_t> stamp = timestamp_us(buf.timestamp);
      out.timestamp_us = stamp.value_or(0);
      // A timestamp no clock gives is damage too (found by fuzzing: it overflowed here).
      out.driver_error = (buf.flags & V4L2_BUF_FLAG_ERROR) != 0 || !ok || !stamp;
      out.monotonic_clock = (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
      if (ok && xioctl(VIDIOC_QBUF, &buf) < 0) {
        fail("VIDIOC_QBUF", errno);
        return CaptureStatus::kLost;
      }
      return CaptureStatus::kFrame;
    }
    // Any error but "nothing yet" (ENODEV, EIO after an unplug; EINVAL if the driver reset the
    // queue) needs a close and reopen.
    if (errno != EAGAIN) {
      fail("VIDIOC_DQBUF", errno);
      return CaptureStatus::kLost;
    }
    const std::int64_t left = deadline - now_ms();
    if (left <= 0) return CaptureStatus::kTimeout;
    pollfd p{fd_, POLLIN, 0};
    const int r = io_.poll(&p, 1, static_cast<int>(left));
    if (r < 0 && errno != EINTR) {
      fail("poll", errno);
      return CaptureStatus::kLost;
    }
    if (r > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL)) && !(p.revents & POLLIN)) {
      // Let DQBUF name the error (ENODEV after a disconnect); if it has none, poll's flag stands.
      if (poll_error) {
        error_ = spec_.path + ": poll: device reported an error (revents " +
                 std::to_string(p.revents) + ")";
        return CaptureStatus::kLost;
      }
      poll_error = true;
    }
  }
}

void V4l2CaptureNode::close() {
  if (fd_ < 0) return;
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(VIDIOC_STREAMOFF, &type);  // may fail on a vanished device; closing frees it anyway
    streaming_ = false;
  }
  for (const Buffer& b : buffers_) io_.munmap(b.start, b.length);
  buffers_.clear();
  io_.close(fd_);
  fd_ = -1;
}

}  // namespace drivers
