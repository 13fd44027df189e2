#include "cell/camera_set.h"

#include <future>

#include "drivers/camera_registry.h"
#include "drivers/monitored_depth_camera.h"
#include "sim_hw/simulated_cameras.h"

namespace cell {

CameraSet::CameraSet() {
  drivers::register_real_depth_cameras();
  sim_hw::register_simulated_depth_cameras();
}

std::string CameraSet::open(const std::vector<drivers::CameraConfig>& configs) {
  std::string first_problem;
  for (const auto& config : configs) {
    CameraSlot slot;
    slot.config = config;
    try {
      slot.camera = drivers::make_monitored_depth_camera(config.backend);
      drivers::DriverResult r = slot.camera->configure(config);
      if (r.ok) r = slot.camera->activate();
      if (!r.ok) {
        slot.last_problem = r.message;
        slot.camera.reset();
      }
    } catch (const std::exception& e) {  // unknown back-end
      slot.last_problem = e.what();
      slot.camera.reset();
    }
    if (!slot.camera && first_problem.empty()) {
      first_problem = "camera " + config.name + ": cannot open (" + slot.last_problem + ")";
    }
    slots_.push_back(std::move(slot));
  }
  return first_problem;
}

void CameraSet::close() {
  for (auto& s : slots_) {
    if (s.camera) s.camera->deactivate();
  }
  slots_.clear();
}

void CameraSet::read_all(std::vector<drivers::DepthFrame>& frames) {
  std::vector<drivers::DepthFrame> got(slots_.size());
  std::vector<std::future<drivers::ReadStatus>> reads;
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    if (!slots_[i].camera) {
      reads.emplace_back();
      continue;
    }
    try {
      reads.push_back(std::async(std::launch::async, [this, i, &got] {
        return slots_[i].camera->read(got[i]);
      }));
    } catch (const std::exception&) {  // no thread available: read here instead
      std::promise<drivers::ReadStatus> p;
      p.set_value(slots_[i].camera->read(got[i]));
      reads.push_back(p.get_future());
    }
  }
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    CameraSlot& s = slots_[i];
    if (!reads[i].valid()) continue;
    s.last_status = reads[i].get();
    if (s.last_status == drivers::ReadStatus::kFrame) {
      s.last_good_host_us = got[i].host_time_us;
      s.last_problem.clear();
      frames.push_back(std::move(got[i]));
    } else {
      const std::string why = s.camera->health().message;
      s.last_problem = std::string(drivers::to_string(s.last_status)) + (why.empty() ? "" : ": " + why);
    }
  }
}

bool CameraSet::fresh(int i, std::int64_t now_us, double stale_ms) const {
  const CameraSlot& s = slots_[i];
  return s.camera && s.last_good_host_us > 0 && (now_us - s.last_good_host_us) <= stale_ms * 1000.0;
}

drivers::CameraHealth CameraSet::health(int i) const {
  if (!slots_[i].camera) {
    drivers::CameraHealth h;
    h.state = drivers::CameraState::kLost;
    h.message = slots_[i].last_problem;
    return h;
  }
  return slots_[i].camera->health();
}

}  // namespace cell
