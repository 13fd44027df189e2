// The V4L2 back-end (drivers/v4l2_d415_camera.h over drivers/v4l2_capture_node.h) against a device
// whose every answer comes from the fuzzer: capabilities, the format and frame interval it grants,
// the buffers it hands out (count, length), and each dequeued buffer (index, bytes used, flags,
// sequence, timestamp, contents), plus errors anywhere. A buggy or hostile uvcvideo node, a
// firmware that reports nonsense, must never crash the cell or hang a read.
#include <fuzzer/FuzzedDataProvider.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

#include "drivers/v4l2_d415_camera.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

class HostileDevice : public drivers::V4l2Io {
 public:
  explicit HostileDevice(FuzzedDataProvider& in) : in_(in) {}
  ~HostileDevice() override {
    for (auto& [address, length] : mapped_) std::free(address);
  }

  int open(const char*, int) override {
    if (fail()) return -1;
    return next_fd_++;
  }
  int close(int) override { return 0; }

  int ioctl(int, unsigned long request, void* arg) override {
    if (fail()) return -1;
    switch (request) {
      case VIDIOC_QUERYCAP: {
        auto* cap = static_cast<v4l2_capability*>(arg);
        in_.ConsumeData(cap->card, sizeof(cap->card) - 1);  // any bytes, NUL-terminated
        cap->capabilities = pick<std::uint32_t>(V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING);
        cap->device_caps = pick<std::uint32_t>(V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING);
        return 0;
      }
      case VIDIOC_S_FMT: {
        auto* f = static_cast<v4l2_format*>(arg);
        if (in_.ConsumeBool()) f->fmt.pix.width = in_.ConsumeIntegral<std::uint32_t>();
        if (in_.ConsumeBool()) f->fmt.pix.height = in_.ConsumeIntegral<std::uint32_t>();
        f->fmt.pix.bytesperline = in_.ConsumeIntegral<std::uint32_t>();
        f->fmt.pix.sizeimage = in_.ConsumeIntegral<std::uint32_t>();
        return 0;
      }
      case VIDIOC_S_PARM: {
        auto* p = static_cast<v4l2_streamparm*>(arg);
        p->parm.capture.capability = in_.ConsumeIntegral<std::uint32_t>();
        if (in_.ConsumeBool()) {
          p->parm.capture.timeperframe.numerator = in_.ConsumeIntegral<std::uint32_t>();
          p->parm.capture.timeperframe.denominator = in_.ConsumeIntegral<std::uint32_t>();
        }
        return 0;
      }
      case VIDIOC_REQBUFS: {
        auto* r = static_cast<v4l2_requestbuffers*>(arg);
        if (in_.ConsumeBool()) r->count = in_.ConsumeIntegral<std::uint32_t>();
        return 0;
      }
      case VIDIOC_QUERYBUF: {
        auto* b = static_cast<v4l2_buffer*>(arg);
        b->length = in_.ConsumeIntegral<std::uint32_t>();
        b->m.offset = in_.ConsumeIntegral<std::uint32_t>();
        return 0;
      }
      case VIDIOC_DQBUF: {
        if (in_.remaining_bytes() == 0) {
          errno = EAGAIN;
          return -1;
        }
        auto* b = static_cast<v4l2_buffer*>(arg);
        b->index = in_.ConsumeBool() ? in_.ConsumeIntegral<std::uint32_t>() : in_.ConsumeIntegralInRange<std::uint32_t>(0, 3);
        b->bytesused = in_.ConsumeIntegral<std::uint32_t>();
        b->flags = in_.ConsumeIntegral<std::uint32_t>();
        b->sequence = in_.ConsumeIntegral<std::uint32_t>();
        b->timestamp.tv_sec = in_.ConsumeIntegral<std::int64_t>();
        b->timestamp.tv_usec = in_.ConsumeIntegral<std::int64_t>();
        // The frame's bytes: what the device wrote into the buffer it hands back.
        for (auto& [address, length] : mapped_) {
          const std::size_t n = std::min<std::size_t>(length, in_.ConsumeIntegralInRange<std::size_t>(0, 64));
          in_.ConsumeData(address, n);
        }
        return 0;
      }
      default:  // QBUF, STREAMON, STREAMOFF
        return 0;
    }
  }

  void* mmap(std::size_t length, int, off_t) override {
    // A device's buffers are real memory of the length it reported; beyond 16 MiB (a 4K YUYV
    // frame) this stand-in says what a kernel short of memory says.
    if (fail() || length == 0 || length > (16u << 20)) {
      errno = ENOMEM;
      return MAP_FAILED;
    }
    void* address = std::calloc(length, 1);
    mapped_.emplace_back(address, length);
    return address;
  }
  int munmap(void* address, std::size_t) override {
    std::erase_if(mapped_, [&](const auto& m) { return m.first == address; });
    std::free(address);
    return 0;
  }
  int poll(pollfd* fds, nfds_t, int) override {
    if (fail()) return -1;
    fds->revents = static_cast<short>(in_.ConsumeIntegral<std::uint16_t>());
    return in_.ConsumeIntegralInRange<int>(0, 1);
  }

 private:
  // Rarely, a call fails with an error a device can give.
  bool fail() {
    if (in_.ConsumeIntegralInRange<int>(0, 31) != 0) return false;
    static constexpr int kErrors[] = {ENODEV, EIO, EINVAL, EBUSY, EAGAIN, EINTR};
    errno = in_.PickValueInArray(kErrors);
    return true;
  }
  template <typename T>
  T pick(T usual) {
    return in_.ConsumeBool() ? usual : in_.ConsumeIntegral<T>();
  }

  FuzzedDataProvider& in_;
  int next_fd_ = 3;
  std::vector<std::pair<void*, std::size_t>> mapped_;  // in mapping order: the same input, the same run
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  drivers::CameraConfig config;
  config.name = "cam_fuzz";
  config.backend = "v4l2";
  const bool color = in.ConsumeBool();
  config.uri = color ? "depth=/dev/video0,color=/dev/video2" : "depth=/dev/video0";
  // Small modes keep each input fast; the sizes are the config's, the device's answers are fuzzed.
  config.depth_mode = {in.ConsumeIntegralInRange<int>(1, 16), in.ConsumeIntegralInRange<int>(1, 16), 30};
  config.color_mode = {in.ConsumeIntegralInRange<int>(1, 16), in.ConsumeIntegralInRange<int>(1, 16), 30};
  config.depth_intrinsics.width = config.depth_mode.width;
  config.depth_intrinsics.height = config.depth_mode.height;
  config.color_intrinsics.width = config.color_mode.width;
  config.color_intrinsics.height = config.color_mode.height;
  config.depth_unit_mm = in.ConsumeBool() ? 1.0 : 0.1;
  config.read_timeout = std::chrono::milliseconds(0);

  auto device = std::make_shared<HostileDevice>(in);
  {
    drivers::V4l2D415Camera camera(device);
    if (!camera.configure(config).ok || !camera.activate().ok) return 0;
    drivers::DepthFrame frame;
    for (int i = 0; i < 8 && in.remaining_bytes() > 0; ++i) {
      const drivers::ReadStatus status = camera.read(frame);
      if (status == drivers::ReadStatus::kFrame || status == drivers::ReadStatus::kStale) {
        if (!frame.rgb.empty() &&
            frame.rgb.size() != static_cast<std::size_t>(frame.color_intrinsics.width) * frame.color_intrinsics.height * 3) {
          std::abort();  // colour of another size than it says
        }
      }
    }
    camera.deactivate();
  }
  return 0;
}
