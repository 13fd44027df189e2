// libprepreg_openni2_sim: an OpenNI2 device driver (loaded by OpenNI2 from its driver repository
// like Debian's libPS1080 or libOniFile) that exposes simulated D415s. The device list comes from
// the JSON file named by PREPREG_OPENNI2_SIM_CONFIG (see openni2_sim_config.h); each device reads
// its frames from a drivers::DepthCamera made through the back-end registry. This plug-in is its
// own shared library with its own copy of the registry, so it registers the back-ends itself.
//
// Test hook: PREPREG_OPENNI2_SIM_TEST_BACKENDS=1 also registers "test_pattern" (known frames, a
// scripted death; see test_pattern_camera.h), for tests that must check frames bit-exact.
//
// Disconnects: when a device's source reports kLost, OpenNI2 is told the device is gone; with
// replug_after_ms >= 0 it is announced again that long afterwards, as a re-plugged USB camera is
// (OpenNI2 only reopens a URI after its driver announces it again).

#include <algorithm>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

// OniDriverAPI.h's ONI_EXPORT_DRIVER uses OpenNI2's internal allocation macros.
#define XN_NEW(type, ...) new type(__VA_ARGS__)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "drivers/camera_registry.h"
#include "sim_hw/openni2_sim_config.h"
#include "sim_hw/openni2_sim_device.h"
#include "sim_hw/simulated_cameras.h"
#include "sim_hw/test_pattern_camera.h"

namespace sim_hw {
namespace {

constexpr const char* kTestBackendsVariable = "PREPREG_OPENNI2_SIM_TEST_BACKENDS";

void copy_field(char (&field)[ONI_MAX_STR], const std::string& text) {
  std::strncpy(field, text.c_str(), ONI_MAX_STR - 1);
  field[ONI_MAX_STR - 1] = '\0';
}

class OpenNI2SimDriver : public oni::driver::DriverBase {
 public:
  explicit OpenNI2SimDriver(OniDriverServices* services) : DriverBase(services) {}

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected,
                       oni::driver::DeviceDisconnectedCallback disconnected,
                       oni::driver::DeviceStateChangedCallback state_changed, void* cookie) override {
    DriverBase::initialize(connected, disconnected, state_changed, cookie);
    drivers::register_real_depth_cameras();
    register_simulated_depth_cameras();
    const char* hook = std::getenv(kTestBackendsVariable);
    if (hook != nullptr && std::string(hook) == "1") register_test_pattern_camera();
    const char* path = std::getenv(kOpenNI2SimConfigVariable);
    if (path == nullptr || *path == '\0') return ONI_STATUS_OK;  // loaded, but no devices
    try {
      configs_ = read_openni2_sim_config(path);
    } catch (const std::exception& e) {
      getServices().errorLoggerAppend("prepreg-sim: %s", e.what());
      return ONI_STATUS_ERROR;
    }
    infos_.resize(configs_.size());
    replug_at_.assign(configs_.size(), Clock::time_point::max());
    for (std::size_t i = 0; i < configs_.size(); ++i) {
      OniDeviceInfo& info = infos_[i];
      std::memset(&info, 0, sizeof(info));
      copy_field(info.uri, kOpenNI2SimUriPrefix + configs_[i].source.name);
      copy_field(info.vendor, "Intel (simulated by prepreg sim_hw)");
      copy_field(info.name, "RealSense D415 (simulated)");
      info.usbVendorId = 0x8086;
      info.usbProductId = 0x0ad3;
      deviceConnected(&info);
    }
    replug_thread_ = std::thread([this] { replug_loop(); });
    return ONI_STATUS_OK;
  }

  oni::driver::DeviceBase* deviceOpen(const char* uri, const char* /*mode*/) override {
    const int i = index_of(uri);
    if (i < 0) {
      getServices().errorLoggerAppend("prepreg-sim: no simulated device \"%s\"", uri);
      return nullptr;
    }
    std::unique_ptr<drivers::DepthCamera> source;
    try {
      source = drivers::make_depth_camera(configs_[i].source.backend);
    } catch (const std::exception& e) {
      getServices().errorLoggerAppend("prepreg-sim: device \"%s\": %s", uri, e.what());
      return nullptr;
    }
    auto* device =
        new OpenNI2SimDevice(configs_[i], std::move(source), getServices(), [this, i] { lost(i); });
    if (!device->start_source()) {
      delete device;
      return nullptr;
    }
    return device;
  }

  void deviceClose(oni::driver::DeviceBase* device) override { delete device; }

  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (replug_thread_.joinable()) replug_thread_.join();
  }

 private:
  using Clock = std::chrono::steady_clock;

  int index_of(const char* uri) const {
    for (std::size_t i = 0; i < infos_.size(); ++i) {
      if (std::strcmp(infos_[i].uri, uri) == 0) return static_cast<int>(i);
    }
    return -1;
  }

  // Called from a device's pump (thread or reader) when its source died.
  void lost(int i) {
    deviceDisconnected(&infos_[i]);
    if (configs_[i].replug_after_ms < 0) return;
    {
      std::lock_guard lock(mutex_);
      replug_at_[i] = Clock::now() + std::chrono::milliseconds(configs_[i].replug_after_ms);
    }
    wake_.notify_all();
  }

  void replug_loop() {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      const auto earliest = std::min_element(replug_at_.begin(), replug_at_.end());
      const auto next = earliest == replug_at_.end() ? Clock::time_point::max() : *earliest;
      if (next == Clock::time_point::max()) {
        wake_.wait(lock);
        continue;
      }
      if (wake_.wait_until(lock, next) != std::cv_status::timeout) continue;
      for (std::size_t i = 0; i < replug_at_.size(); ++i) {
        if (replug_at_[i] > Clock::now()) continue;
        replug_at_[i] = Clock::time_point::max();
        lock.unlock();
        deviceConnected(&infos_[i]);
        lock.lock();
      }
    }
  }

  std::vector<OpenNI2SimDeviceConfig> configs_;
  std::vector<OniDeviceInfo> infos_;  // fixed after initialize(); OpenNI2 keeps pointers to them
  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Clock::time_point> replug_at_;
  bool stopping_ = false;
  std::thread replug_thread_;
};

}  // namespace
}  // namespace sim_hw

ONI_EXPORT_DRIVER(sim_hw::OpenNI2SimDriver)
