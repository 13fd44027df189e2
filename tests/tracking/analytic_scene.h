#pragma once
// Depth frames of known analytic surfaces, for the tracker tests and benchmark: each pixel's ray
// is intersected with the surfaces exactly (a plane, a cylinder, a sagging sheet z = f(x, y)
// solved per ray by Newton steps), so every fused point has a true surface to be compared with.
// Noise follows a D415-like model: Gaussian along the depth axis with standard deviation
// sigma_1m * z^2 (1.5 mm at 1 m, 6 mm at 2 m), seeded; depth is rounded to whole millimetres.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"
#include "tracking/surface_mesh.h"

namespace tracking::testing {

using Rgb = std::array<std::uint8_t, 3>;

class AnalyticSurface {
 public:
  explicit AnalyticSurface(Rgb rgb) : rgb_(rgb) {}
  virtual ~AnalyticSurface() = default;
  // Smallest ray parameter t > 0 where origin + t * direction meets the surface.
  virtual std::optional<double> intersect(const Vec3& origin, const Vec3& direction) const = 0;
  // Distance (m) from a point to the surface (exact or first order for points near it).
  virtual double distance(const Vec3& point) const = 0;
  const Rgb& rgb() const { return rgb_; }

 private:
  Rgb rgb_;
};

// Rectangle centred on `centre`, spanned by unit axes u, v with half sizes (infinite if <= 0).
class PlaneSurface : public AnalyticSurface {
 public:
  PlaneSurface(Vec3 centre, Vec3 u, Vec3 v, double half_u, double half_v, Rgb rgb);
  std::optional<double> intersect(const Vec3& origin, const Vec3& direction) const override;
  double distance(const Vec3& point) const override;

 private:
  Vec3 centre_, u_, v_, n_;
  double half_u_, half_v_;
};

// Cylinder of `radius` about the axis through `centre` along unit `axis`, |axial| <= half_length.
class CylinderSurface : public AnalyticSurface {
 public:
  CylinderSurface(Vec3 centre, Vec3 axis, double radius, double half_length, Rgb rgb);
  std::optional<double> intersect(const Vec3& origin, const Vec3& direction) const override;
  double distance(const Vec3& point) const override;

 private:
  Vec3 centre_, axis_;
  double radius_, half_length_;
};

// Sheet held at its border and sagging: z = z0 + slope_x x + slope_y y
//   - sag cos(pi x / width) cos(pi y / height) + ripple sin(2 pi x / width) sin(pi y / height),
// over |x| <= width/2, |y| <= height/2 (cell frame, m).
struct SheetShape {
  double width_m = 1.17, height_m = 0.975;
  double z0_m = 0.9, sag_m = 0.12, slope_x = 0.0, slope_y = 0.0, ripple_m = 0.0;
  double height_at(double x, double y) const;
  Eigen::Vector2d gradient_at(double x, double y) const;
};

class SaggingSheet : public AnalyticSurface {
 public:
  SaggingSheet(SheetShape shape, Rgb rgb);
  std::optional<double> intersect(const Vec3& origin, const Vec3& direction) const override;
  double distance(const Vec3& point) const override;
  const SheetShape& shape() const { return shape_; }
  // A grid mesh (cols x rows) of the sheet: vertices on the surface above the grid points, no
  // rest coordinates (the flat grid is not the material of a sheet stretched over z = f(x, y)).
  SurfaceMesh mesh(int cols, int rows) const;

 private:
  SheetShape shape_;
};

struct Scene {
  std::vector<std::shared_ptr<const AnalyticSurface>> surfaces;
  Rgb background{220, 220, 220};
  // Nearest hit: surface index and ray parameter, or nullopt.
  std::optional<std::pair<int, double>> cast(const Vec3& origin, const Vec3& direction) const;
};

struct CameraSetup {
  std::string name;
  drivers::Intrinsics depth, color;
  Eigen::Isometry3d camera_to_cell = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d depth_to_color = Eigen::Isometry3d::Identity();
};

// A camera at `position` looking at `target` (cell z up), D415-like: ~65 deg horizontal field
// of view, colour camera 15 mm to the depth camera's right with a wider lens and a lower
// resolution, so the colour lookup through depth_to_color is exercised.
CameraSetup look_at_camera(const std::string& name, const Vec3& position, const Vec3& target,
                           int width, int height);

struct NoiseModel {
  double sigma_at_1m_m = 0.0015;  // 0 = exact depth (still rounded to mm)
  std::uint32_t seed = 1;
};

drivers::DepthFrame render_frame(const Scene& scene, const CameraSetup& camera,
                                 const NoiseModel& noise);

// The standard test cell: a dark sagging sheet (1.17 x 0.975 m, 0.78-0.9 m high), a light
// floor, and three cameras around and above it, 1.4-1.5 m from the sheet's centre (0.85-2.1 m
// from its nearest and farthest points), each aimed at its own part of the sheet.
std::vector<CameraSetup> three_cameras(int width, int height);
Scene sheet_scene(const SheetShape& shape,
                  std::shared_ptr<const SaggingSheet>* sheet_out = nullptr);

}  // namespace tracking::testing
