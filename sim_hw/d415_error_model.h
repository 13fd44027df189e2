#pragma once
// A D415-like measurement model applied to rendered truth: what the stereo depth and the colour
// sensor report instead of the exact scene. Depth: Gaussian noise whose RMS grows with distance
// squared (stereo disparity error is constant in pixels, so depth error ~ z^2 / (f b)), a small
// bias also ~ z^2, quantisation to whole depth units, and holes where a real D415 has them:
// grazing surfaces, depth discontinuities, the stereo shadow (seen by the left imager only), out
// of range, and a small random dropout. Colour: Lambert shading plus slight sensor noise.

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "drivers/depth_camera.h"
#include "sim_hw/depth_renderer.h"
#include "sim_hw/render_scene.h"

namespace sim_hw {

struct D415NoiseConfig {
  double sigma_at_1m_mm = 1.5;    // depth noise RMS at 1 m; RMS = this * z^2 (z in m)
  double bias_at_1m_mm = 1.0;     // systematic depth offset at 1 m (+ = too far); * z^2
  double grazing_limit_deg = 80;  // invalid if the angle between view ray and normal exceeds it
  double edge_jump_m = 0.03;      // invalid next to a depth step (off the tangent plane) above this
  double min_range_m = 0.3, max_range_m = 10.0;
  double dropout_fraction = 0.002;  // random missing pixels
  bool stereo_shadow = true;        // invalid where the right imager cannot see the point
  double shadow_tolerance_m = 0.01;  // occluder must be this much nearer to count
  double color_noise_counts = 2.0;   // colour noise RMS per channel (0..255 counts)
  double ambient = 0.35;             // colour = albedo * (ambient + (1-ambient) |n.l|)
};

// Turns the left view (and, for the stereo shadow, the right imager's view; may be null) into a
// D415 depth image: uint16 counts of depth_unit_mm, 0 = invalid. `right_in_left` is the right
// imager's pose in the left (depth) frame.
void make_depth_image(const RenderedView& left, const RenderedView* right,
                      const drivers::Intrinsics& intrinsics, const Eigen::Isometry3d& right_in_left,
                      const D415NoiseConfig& noise, double depth_unit_mm, std::mt19937_64& rng,
                      std::vector<std::uint16_t>& depth);

// Shades a view rendered from the colour camera into RGB8 (row-major, 3 bytes per pixel).
// light_in_camera: unit direction towards the light in that camera's frame.
void make_color_image(const RenderedView& view, const RenderScene& scene,
                      const Eigen::Vector3d& light_in_camera, const D415NoiseConfig& noise,
                      std::mt19937_64& rng, std::vector<std::uint8_t>& rgb);

}  // namespace sim_hw
