#pragma once
// The cell's depth cameras: opened by config through the back-end registry (real back-ends and
// sim_hw's "simulated" are registered on construction), each behind the generic frame monitor.
// read_all() reads every camera at once (one thread each), so a slow camera holds the cycle up
// by at most its own read timeout, never by the sum; it never throws.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"

namespace cell {

struct CameraSlot {
  drivers::CameraConfig config;
  std::unique_ptr<drivers::DepthCamera> camera;  // monitored
  drivers::ReadStatus last_status = drivers::ReadStatus::kNotActive;
  std::int64_t last_good_host_us = 0;  // host clock of the last usable frame (0: none yet)
  std::string last_problem;            // why the camera last failed to open or deliver
};

class CameraSet {
 public:
  CameraSet();
  // Opens (configure + activate) every camera; a camera that cannot open stays in the set
  // without a device and its reason is kept. Returns "" when all opened, else the first reason.
  std::string open(const std::vector<drivers::CameraConfig>& configs);
  void close();

  // One read of every camera in parallel; frames with status kFrame are appended to `frames`.
  void read_all(std::vector<drivers::DepthFrame>& frames);

  // Fresh: delivered a usable frame within stale_ms of now (host clock, us).
  bool fresh(int i, std::int64_t now_us, double stale_ms) const;
  int size() const { return static_cast<int>(slots_.size()); }
  const CameraSlot& slot(int i) const { return slots_[i]; }
  drivers::CameraHealth health(int i) const;

 private:
  std::vector<CameraSlot> slots_;
};

}  // namespace cell
