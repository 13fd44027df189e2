#include "drivers/monitored_depth_camera.h"

#include <algorithm>

#include "drivers/camera_registry.h"
#include "drivers/frame_checks.h"

namespace drivers {

MonitoredDepthCamera::MonitoredDepthCamera(std::unique_ptr<DepthCamera> inner)
    : inner_(std::move(inner)) {}

DriverResult MonitoredDepthCamera::configure(const CameraConfig& config) {
  config_ = config;
  reset_stream_baselines();
  return inner_->configure(config);
}

DriverResult MonitoredDepthCamera::activate() {
  reset_stream_baselines();
  degraded_ = false;
  message_.clear();
  return inner_->activate();
}

DriverResult MonitoredDepthCamera::deactivate() { return inner_->deactivate(); }

void MonitoredDepthCamera::reset_stream_baselines() {
  have_previous_ = false;
  identical_run_ = 0;
}

void MonitoredDepthCamera::degrade(std::string why) {
  degraded_ = true;
  message_ = std::move(why);
}

ReadStatus MonitoredDepthCamera::read(DepthFrame& frame) {
  const ReadStatus status = inner_->read(frame);
  switch (status) {
    case ReadStatus::kFrame:
    case ReadStatus::kStale:
    case ReadStatus::kFrozen:
      return check(frame, status);
    case ReadStatus::kTimeout:
      degrade("no frame within " + std::to_string(config_.read_timeout.count()) + " ms");
      return status;
    case ReadStatus::kLost:
      reset_stream_baselines();  // a reopened device restarts its counters and clock
      return status;
    case ReadStatus::kCorrupt:
      ++corrupt_;
      degrade("corrupt frame (reported by the back-end)");
      return status;
    case ReadStatus::kNotActive:
      return status;
  }
  return status;
}

ReadStatus MonitoredDepthCamera::check(DepthFrame& frame, ReadStatus inner_status) {
  // Sequence and clock bookkeeping first: a corrupt frame still tells us a frame was sent.
  bool stale = inner_status == ReadStatus::kStale;
  std::string stale_why = stale ? "back-end reported a stale frame" : "";
  const std::int64_t offset_us = frame.host_time_us - frame.device_time_us;
  if (have_previous_) {
    if (frame.sequence > last_sequence_ + 1) dropped_ += frame.sequence - last_sequence_ - 1;
    if (frame.device_time_us <= last_device_time_us_) {
      stale = true;
      stale_why = "device timestamp did not advance (" + std::to_string(frame.device_time_us) +
                  " us after " + std::to_string(last_device_time_us_) + " us)";
    } else {
      // Let the baseline rise by 1 ms per second of device time (1000 ppm), far above a
      // crystal's drift, so clock drift never reads as staleness.
      const std::int64_t leak_us = (frame.device_time_us - last_device_time_us_) / 1000;
      offset_baseline_us_ = std::min(offset_us, offset_baseline_us_ + leak_us);
      const std::int64_t late_us = offset_us - offset_baseline_us_;
      if (late_us > std::chrono::microseconds(config_.stale_after).count()) {
        stale = true;
        stale_why = "frame arrived " + std::to_string(late_us / 1000) +
                    " ms later than the device clock says (stale_after " +
                    std::to_string(config_.stale_after.count()) + " ms)";
      }
    }
  } else {
    offset_baseline_us_ = offset_us;
  }
  last_device_time_us_ = have_previous_ ? std::max(last_device_time_us_, frame.device_time_us)
                                        : frame.device_time_us;
  have_previous_ = true;
  last_sequence_ = frame.sequence;

  std::string reason = corrupt_frame_reason(frame);
  if (!reason.empty()) {
    ++corrupt_;
    identical_run_ = 0;
    degrade("corrupt frame " + std::to_string(frame.sequence) + ": " + reason);
    return ReadStatus::kCorrupt;
  }

  ++frames_;
  last_frame_host_time_us_ = frame.host_time_us;
  const std::uint64_t hash = depth_content_hash(frame);
  identical_run_ = (identical_run_ > 0 && hash == last_hash_) ? identical_run_ + 1 : 1;
  last_hash_ = hash;
  if (inner_status == ReadStatus::kFrozen || identical_run_ >= config_.frozen_after_frames) {
    ++frozen_;
    degrade("frozen stream: " + std::to_string(identical_run_) + " identical depth images in a row");
    return ReadStatus::kFrozen;
  }
  if (stale) {
    ++stale_;
    degrade("stale frame " + std::to_string(frame.sequence) + ": " + stale_why);
    return ReadStatus::kStale;
  }
  degraded_ = false;
  message_.clear();
  return ReadStatus::kFrame;
}

CameraHealth MonitoredDepthCamera::health() const {
  CameraHealth h = inner_->health();
  h.frames = frames_;
  h.dropped = dropped_;
  h.stale = stale_;
  h.frozen = frozen_;
  h.last_frame_host_time_us = last_frame_host_time_us_;
  if (degraded_ && (h.state == CameraState::kActive || h.state == CameraState::kDegraded)) {
    h.state = CameraState::kDegraded;
    h.message = message_;
  }
  return h;
}

std::unique_ptr<DepthCamera> make_monitored_depth_camera(const std::string& backend) {
  return std::make_unique<MonitoredDepthCamera>(make_depth_camera(backend));
}

}  // namespace drivers
