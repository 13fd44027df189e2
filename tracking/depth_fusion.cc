// Back-projection of depth pixels and colour lookup (stage 1).
#include "tracking/depth_fusion.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tracking {
namespace {

bool same_intrinsics(const drivers::Intrinsics& a, const drivers::Intrinsics& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.k1 == b.k1 && a.k2 == b.k2 && a.p1 == b.p1 &&
         a.p2 == b.p2 && a.k3 == b.k3;
}

bool has_distortion(const drivers::Intrinsics& in) {
  return in.k1 != 0.0 || in.k2 != 0.0 || in.p1 != 0.0 || in.p2 != 0.0 || in.k3 != 0.0;
}

// Brown-Conrady forward model on normalised coordinates (as OpenCV and librealsense).
Eigen::Vector2d distort(const drivers::Intrinsics& in, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y(), r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (in.k1 + r2 * (in.k2 + r2 * in.k3));
  return {x * radial + 2.0 * in.p1 * x * y + in.p2 * (r2 + 2.0 * x * x),
          y * radial + in.p1 * (r2 + 2.0 * y * y) + 2.0 * in.p2 * x * y};
}

// Inverse of distort() by fixed-point iteration: converges for the mild distortion of depth
// and colour cameras (|correction| well below 1) in a handful of steps.
Eigen::Vector2d undistort(const drivers::Intrinsics& in, const Eigen::Vector2d& distorted) {
  Eigen::Vector2d p = distorted;
  for (int it = 0; it < 10; ++it) p += distorted - distort(in, p);
  return p;
}

}  // namespace

const char* to_string(FrameStatus status) {
  switch (status) {
    case FrameStatus::kOk:
      return "ok";
    case FrameStatus::kEmpty:
      return "empty";
    case FrameStatus::kSizeMismatch:
      return "size mismatch";
    case FrameStatus::kBadIntrinsics:
      return "bad intrinsics";
    case FrameStatus::kNonFinitePose:
      return "non-finite pose";
  }
  return "unknown";
}

std::string check_intrinsics(const drivers::Intrinsics& in) {
  if (in.width <= 0 || in.height <= 0) {
    return fmt::format("image size {}x{} is not positive", in.width, in.height);
  }
  const double values[] = {in.fx, in.fy, in.cx, in.cy, in.k1, in.k2, in.p1, in.p2, in.k3};
  for (double v : values) {
    if (!std::isfinite(v)) return "intrinsics are not finite";
  }
  if (in.fx <= 0.0 || in.fy <= 0.0) return fmt::format("focal length {} x {} px", in.fx, in.fy);
  return {};
}

std::string check_pose(const Eigen::Isometry3d& pose) {
  if (!pose.matrix().allFinite()) return "pose is not finite";
  // A pose read from a config can be finite and still not a rotation (a typo in one entry).
  const Eigen::Matrix3d r = pose.linear();
  if (!(r.transpose() * r).isIdentity(1e-6) || r.determinant() < 0.0) {
    return "pose rotation is not orthonormal";
  }
  return {};
}

const std::vector<Eigen::Vector2f>& DepthFusion::rays_for(const drivers::Intrinsics& in) {
  for (const RayTable& t : ray_tables_) {
    if (same_intrinsics(t.intrinsics, in)) return t.rays;
  }
  RayTable table{in, {}};
  table.rays.resize(static_cast<std::size_t>(in.width) * in.height);
  const bool distorted = has_distortion(in);
  for (int v = 0; v < in.height; ++v) {
    for (int u = 0; u < in.width; ++u) {
      Eigen::Vector2d p((u - in.cx) / in.fx, (v - in.cy) / in.fy);
      if (distorted) p = undistort(in, p);
      table.rays[static_cast<std::size_t>(v) * in.width + u] = p.cast<float>();
    }
  }
  // Cameras of one cell are few; keep a bounded cache so a stream of odd intrinsics cannot grow it.
  if (ray_tables_.size() >= 8) ray_tables_.erase(ray_tables_.begin());
  ray_tables_.push_back(std::move(table));
  return ray_tables_.back().rays;
}

FrameReport DepthFusion::add_frame(const drivers::DepthFrame& frame, int camera_index,
                                   SensorCloud& cloud) {
  FrameReport report;
  report.camera = frame.camera;
  const drivers::Intrinsics& in = frame.depth_intrinsics;
  const auto reject = [&](FrameStatus status, std::string why) {
    report.status = status;
    report.message = std::move(why);
    return report;
  };
  if (std::string why = check_intrinsics(in); !why.empty()) {
    return reject(FrameStatus::kBadIntrinsics, "depth " + why);
  }
  if (frame.depth_mm.empty()) return reject(FrameStatus::kEmpty, "no depth image");
  const std::size_t pixels = static_cast<std::size_t>(in.width) * in.height;
  if (frame.depth_mm.size() != pixels) {
    return reject(FrameStatus::kSizeMismatch,
                  fmt::format("depth has {} values, intrinsics say {}x{} = {}",
                              frame.depth_mm.size(), in.width, in.height, pixels));
  }
  if (std::string why = check_pose(frame.camera_to_cell); !why.empty()) {
    return reject(FrameStatus::kNonFinitePose, "camera_to_cell: " + why);
  }

  // Colour is optional: a frame without usable colour still gives geometry.
  const drivers::Intrinsics& ci = frame.color_intrinsics;
  bool use_color = false;
  if (ci.width > 0) {
    if (std::string why = check_intrinsics(ci); !why.empty()) {
      report.message = "colour ignored: " + why;
    } else if (frame.rgb.size() != static_cast<std::size_t>(ci.width) * ci.height * 3) {
      report.message = fmt::format("colour ignored: {} bytes for {}x{} RGB", frame.rgb.size(),
                                   ci.width, ci.height);
    } else if (std::string pose = check_pose(frame.depth_to_color); !pose.empty()) {
      report.message = "colour ignored: depth_to_color: " + pose;
    } else {
      use_color = true;
    }
  }
  report.color_used = use_color;

  const std::vector<Eigen::Vector2f>& rays = rays_for(in);
  const int stride = std::max(options_.pixel_stride, 1);
  const int cols = (in.width + stride - 1) / stride, rows = (in.height + stride - 1) / stride;
  const Eigen::Matrix3f r = frame.camera_to_cell.linear().cast<float>();
  const Eigen::Vector3f t = frame.camera_to_cell.translation().cast<float>();
  const Eigen::Matrix3f rc = frame.depth_to_color.linear().cast<float>();
  const Eigen::Vector3f tc = frame.depth_to_color.translation().cast<float>();
  const bool color_distorted = has_distortion(ci);
  const std::uint16_t min_mm =
      static_cast<std::uint16_t>(std::clamp(1e3 * options_.min_depth_m, 1.0, 65535.0));
  const std::uint16_t max_mm =
      static_cast<std::uint16_t>(std::clamp(1e3 * options_.max_depth_m, 1.0, 65535.0));

  // Pixels are processed in parallel into fixed slots, then compacted in order, so the cloud is
  // the same whatever the thread count.
  const std::size_t slots = static_cast<std::size_t>(cols) * rows;
  slot_points_.resize(slots);
  slot_rgb_.resize(3 * slots);
  slot_flags_.resize(slots);
  const bool crop = options_.crop_to_box;
  const Eigen::Array3f box_min = options_.box_min_m.array(), box_max = options_.box_max_m.array();
  constexpr std::uint8_t kOutsideBox = 2;  // slot flags: 0 invalid, 1 valid, 3 valid and coloured
#pragma omp parallel for schedule(static)
  for (int row = 0; row < rows; ++row) {
    const int v = row * stride;
    for (int col = 0; col < cols; ++col) {
      const int u = col * stride;
      const std::size_t slot = static_cast<std::size_t>(row) * cols + col;
      const std::size_t pixel = static_cast<std::size_t>(v) * in.width + u;
      const std::uint16_t d = frame.depth_mm[pixel];
      slot_flags_[slot] = 0;
      if (d < min_mm || d > max_mm) continue;
      const float z = 1e-3f * d;
      const Eigen::Vector3f p_cam(rays[pixel].x() * z, rays[pixel].y() * z, z);
      const Eigen::Vector3f p_cell = r * p_cam + t;
      if (crop && ((p_cell.array() < box_min).any() || (p_cell.array() > box_max).any())) {
        slot_flags_[slot] = kOutsideBox;
        continue;
      }
      slot_points_[slot] = p_cell;
      slot_flags_[slot] = 1;
      slot_rgb_[3 * slot] = slot_rgb_[3 * slot + 1] = slot_rgb_[3 * slot + 2] = 0;
      if (!use_color) continue;
      const Eigen::Vector3f p_col = rc * p_cam + tc;
      if (p_col.z() <= 0.0f) continue;
      Eigen::Vector2d n(p_col.x() / p_col.z(), p_col.y() / p_col.z());
      if (color_distorted) n = distort(ci, n);
      const long cu = std::lround(ci.fx * n.x() + ci.cx), cv = std::lround(ci.fy * n.y() + ci.cy);
      if (cu < 0 || cv < 0 || cu >= ci.width || cv >= ci.height) continue;
      const std::size_t c = 3 * (static_cast<std::size_t>(cv) * ci.width + cu);
      slot_rgb_[3 * slot] = frame.rgb[c];
      slot_rgb_[3 * slot + 1] = frame.rgb[c + 1];
      slot_rgb_[3 * slot + 2] = frame.rgb[c + 2];
      slot_flags_[slot] = 3;  // valid and coloured
    }
  }
  const std::size_t before = cloud.size();
  int outside = 0;
  for (std::size_t s = 0; s < slots; ++s) {
    if (slot_flags_[s] == 0) continue;
    if (slot_flags_[s] == kOutsideBox) {
      ++outside;
      continue;
    }
    cloud.points_m.push_back(slot_points_[s]);
    cloud.rgb.insert(cloud.rgb.end(), &slot_rgb_[3 * s], &slot_rgb_[3 * s] + 3);
    cloud.has_color.push_back(slot_flags_[s] == 3 ? 1 : 0);
    cloud.camera.push_back(static_cast<std::uint8_t>(camera_index));
  }
  report.points = static_cast<int>(cloud.size() - before);
  report.outside_box = outside;
  if (report.points + report.outside_box == 0) return reject(FrameStatus::kEmpty, "no valid depth pixel");
  return report;
}

}  // namespace tracking
