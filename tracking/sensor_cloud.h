#pragma once
// Points fused from the depth cameras, in the cell frame, as parallel arrays (structure of
// arrays: the stages after fusion read positions far more often than colours). float positions:
// 0.1 um steps at 2 m, far below the cameras' millimetre noise, and half the memory traffic.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace tracking {

struct SensorCloud {
  std::vector<Eigen::Vector3f> points_m;  // cell frame (m)
  std::vector<std::uint8_t> rgb;          // 3 per point; 0,0,0 when the colour is unknown
  std::vector<std::uint8_t> has_color;    // 1 when the colour camera saw the point
  std::vector<std::uint8_t> camera;       // index of the source camera in the cycle's frames

  std::size_t size() const { return points_m.size(); }
  void clear() {
    points_m.clear();
    rgb.clear();
    has_color.clear();
    camera.clear();
  }
  void reserve(std::size_t n) {
    points_m.reserve(n);
    rgb.reserve(3 * n);
    has_color.reserve(n);
    camera.reserve(n);
  }
};

}  // namespace tracking
