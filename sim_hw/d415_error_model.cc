#include "sim_hw/d415_error_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sim_hw {
namespace {

// True when the pixel's point is hidden from the right imager by something nearer (the stereo
// shadow: the matcher finds no correspondence there).
bool in_stereo_shadow(const RenderedView& right, const drivers::Intrinsics& k,
                      const Eigen::Isometry3d& left_in_right, const Eigen::Vector3d& p_left,
                      double tolerance_m) {
  const Eigen::Vector3d p = left_in_right * p_left;
  if (p.z() <= 0.0) return true;
  const double u = k.fx * p.x() / p.z() + k.cx, v = k.fy * p.y() / p.z() + k.cy;
  if (!(u > -0.5 && v > -0.5 && u < right.width - 0.5 && v < right.height - 0.5)) return true;  // outside right view
  const int c = int(u + 0.5), r = int(v + 0.5);  // nearest pixel (u, v > -0.5)
  const float z_right = right.depth_m[std::size_t(r) * right.width + c];
  return z_right > 0.0f && z_right < p.z() - tolerance_m;
}

// True next to a depth discontinuity: a 4-neighbour that hit nothing, or whose depth differs by
// more than jump_m from where this pixel's own tangent plane predicts it. Comparing with the
// tangent plane (not the raw depth) keeps steeply sloped but smooth surfaces, e.g. a far floor,
// valid; only real steps (object outlines, overlapping folds) are cut out.
bool next_to_jump(const RenderedView& v, const drivers::Intrinsics& k, int r, int c, float z, double jump_m) {
  const int dr[4] = {-1, 1, 0, 0}, dc[4] = {0, 0, -1, 1};
  const Eigen::Vector3d n = v.normal_cam[std::size_t(r) * v.width + c].cast<double>();
  const double plane = n.dot(Eigen::Vector3d((c - k.cx) / k.fx, (r - k.cy) / k.fy, 1.0) * double(z));
  for (int i = 0; i < 4; ++i) {
    const int rr = r + dr[i], cc = c + dc[i];
    if (rr < 0 || cc < 0 || rr >= v.height || cc >= v.width) continue;
    const float zn = v.depth_m[std::size_t(rr) * v.width + cc];
    if (zn == 0.0f) return true;
    if (std::abs(zn - z) <= jump_m) continue;  // cheap accept: no step of that size at all
    const double nd = n.dot(Eigen::Vector3d((cc - k.cx) / k.fx, (rr - k.cy) / k.fy, 1.0));
    if (std::abs(nd) < 1e-9 || std::abs(zn - plane / nd) > jump_m) return true;
  }
  return false;
}

// Per-pixel random bits: SplitMix64 seeded once per image from the caller's mt19937_64 (the
// Mersenne Twister's refills cost more than the rest of the error model per pixel).
struct PixelBits {
  std::uint64_t state;
  std::uint64_t operator()() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
};

// A standard normal variate from 64 random bits: the sum of 8 uniform bytes (Irwin-Hall), which
// matches a Gaussian to within a few per cent in density and is cut at +-4.9 sigma. Several
// times cheaper than std::normal_distribution, which dominated the frame time.
double unit_gauss(std::uint64_t bits) {
  int sum = 0;
  for (int i = 0; i < 8; ++i) sum += int((bits >> (8 * i)) & 255);
  constexpr double kMean = 8 * 127.5;
  constexpr double kInvSigma = 1.0 / 209.0215;  // sqrt(8 * (256^2 - 1) / 12)
  return (sum - kMean) * kInvSigma;
}

}  // namespace

void make_depth_image(const RenderedView& left, const RenderedView* right,
                      const drivers::Intrinsics& k, const Eigen::Isometry3d& right_in_left,
                      const D415NoiseConfig& noise, double depth_unit_mm, std::mt19937_64& rng,
                      std::vector<std::uint16_t>& depth) {
  depth.assign(std::size_t(left.width) * left.height, 0);
  const Eigen::Isometry3d left_in_right = right_in_left.inverse();
  const double cos_limit = std::cos(noise.grazing_limit_deg * std::numbers::pi / 180.0);
  PixelBits bits{rng()};
  // Dropout threshold on 32 random bits.
  const double dropout_threshold = noise.dropout_fraction * 4294967296.0;
  for (int r = 0; r < left.height; ++r) {
    for (int c = 0; c < left.width; ++c) {
      const std::size_t idx = std::size_t(r) * left.width + c;
      const float z = left.depth_m[idx];
      if (z == 0.0f || z < noise.min_range_m || z > noise.max_range_m) continue;
      const Eigen::Vector3d ray((c - k.cx) / k.fx, (r - k.cy) / k.fy, 1.0);
      const double cos_angle = std::abs(left.normal_cam[idx].cast<double>().dot(ray)) / ray.norm();
      if (cos_angle < cos_limit) continue;
      if (next_to_jump(left, k, r, c, z, noise.edge_jump_m)) continue;
      if (noise.stereo_shadow && right &&
          in_stereo_shadow(*right, k, left_in_right, ray * double(z), noise.shadow_tolerance_m)) {
        continue;
      }
      if (noise.dropout_fraction > 0.0 && double(bits() >> 32) < dropout_threshold) continue;
      const double z2 = double(z) * z;
      const double z_mm = 1000.0 * z + noise.bias_at_1m_mm * z2 + noise.sigma_at_1m_mm * z2 * unit_gauss(bits());
      const double counts = std::floor(z_mm / depth_unit_mm + 0.5);
      if (counts >= 1.0 && counts <= 65535.0) depth[idx] = std::uint16_t(counts);
    }
  }
}

void make_color_image(const RenderedView& view, const RenderScene& scene,
                      const Eigen::Vector3d& light_in_camera, const D415NoiseConfig& noise,
                      std::mt19937_64& rng, std::vector<std::uint8_t>& rgb) {
  const std::size_t n = std::size_t(view.width) * view.height;
  rgb.resize(3 * n);
  const Eigen::Vector3f light = light_in_camera.normalized().cast<float>();
  // Cheap noise: per channel the sum of two uniform bytes (triangular, close enough to sensor
  // noise at a few counts), one 64-bit draw per pixel.
  PixelBits bits{rng()};
  const float scale = float(noise.color_noise_counts) / 104.5f;  // RMS of a sum of 2 bytes
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t s = view.surface[i];
    Albedo colour = scene.background;
    if (s != kNoSurface) {
      const Albedo& albedo = s == kFloorSurface ? scene.floor->albedo : scene.meshes[s].albedo;
      const float lambert = std::abs(view.normal_cam[i].dot(light));
      colour = albedo * float(noise.ambient + (1.0 - noise.ambient) * lambert);
    }
    const std::uint64_t draw = scale > 0.0f ? bits() : 0;
    for (int ch = 0; ch < 3; ++ch) {
      float value = colour[ch];
      if (scale > 0.0f) {
        const std::uint64_t w = draw >> (16 * ch);
        value += scale * float(int(w & 255) + int((w >> 8) & 255) - 255);
      }
      rgb[3 * i + ch] = std::uint8_t(std::clamp(value, 0.0f, 255.0f) + 0.5f);
    }
  }
}

}  // namespace sim_hw
