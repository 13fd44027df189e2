// Ray casting of analytic surfaces into depth and colour images (test support).
#include "tests/tracking/analytic_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tracking::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector2d distort(const drivers::Intrinsics& in, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y(), r2 = x * x + y * y;
  const double radial = 1.0 + in.k1 * r2 + in.k2 * r2 * r2 + in.k3 * r2 * r2 * r2;
  return {x * radial + 2 * in.p1 * x * y + in.p2 * (r2 + 2 * x * x),
          y * radial + in.p1 * (r2 + 2 * y * y) + 2 * in.p2 * x * y};
}

// Ray direction (camera frame, z = 1) of pixel (u, v): the undistorted point whose distortion is
// the pixel's normalised coordinate, found by Gauss-Newton with a finite-difference Jacobian.
Vec3 pixel_ray(const drivers::Intrinsics& in, double u, double v) {
  const Eigen::Vector2d target((u - in.cx) / in.fx, (v - in.cy) / in.fy);
  Eigen::Vector2d p = target;
  if (in.k1 != 0 || in.k2 != 0 || in.k3 != 0 || in.p1 != 0 || in.p2 != 0) {
    for (int it = 0; it < 20; ++it) {
      const Eigen::Vector2d r = distort(in, p) - target;
      if (r.norm() < 1e-13) break;
      Eigen::Matrix2d j;
      const double h = 1e-7;
      j.col(0) = (distort(in, p + Eigen::Vector2d(h, 0)) - distort(in, p)) / h;
      j.col(1) = (distort(in, p + Eigen::Vector2d(0, h)) - distort(in, p)) / h;
      p -= j.lu().solve(r);
    }
  }
  return {p.x(), p.y(), 1.0};
}

}  // namespace

PlaneSurface::PlaneSurface(Vec3 centre, Vec3 u, Vec3 v, double half_u, double half_v, Rgb rgb)
    : AnalyticSurface(rgb),
      centre_(centre),
      u_(u.normalized()),
      v_(v.normalized()),
      n_(u.cross(v).normalized()),
      half_u_(half_u),
      half_v_(half_v) {}

std::optional<double> PlaneSurface::intersect(const Vec3& origin, const Vec3& direction) const {
  const double denom = n_.dot(direction);
  if (std::abs(denom) < 1e-12) return std::nullopt;
  const double t = n_.dot(centre_ - origin) / denom;
  if (t <= 0) return std::nullopt;
  const Vec3 q = origin + t * direction - centre_;
  if (half_u_ > 0 && std::abs(q.dot(u_)) > half_u_) return std::nullopt;
  if (half_v_ > 0 && std::abs(q.dot(v_)) > half_v_) return std::nullopt;
  return t;
}

double PlaneSurface::distance(const Vec3& point) const { return std::abs(n_.dot(point - centre_)); }

CylinderSurface::CylinderSurface(Vec3 centre, Vec3 axis, double radius, double half_length, Rgb rgb)
    : AnalyticSurface(rgb),
      centre_(centre),
      axis_(axis.normalized()),
      radius_(radius),
      half_length_(half_length) {}

std::optional<double> CylinderSurface::intersect(const Vec3& origin, const Vec3& direction) const {
  // |(o + t d - c)_perp|^2 = r^2, a quadratic in t; the nearer positive root within the length.
  const Vec3 oc = origin - centre_;
  const Vec3 dp = direction - direction.dot(axis_) * axis_;
  const Vec3 op = oc - oc.dot(axis_) * axis_;
  const double a = dp.squaredNorm(), b = 2 * dp.dot(op), c = op.squaredNorm() - radius_ * radius_;
  const double disc = b * b - 4 * a * c;
  if (a < 1e-15 || disc < 0) return std::nullopt;
  for (double t : {(-b - std::sqrt(disc)) / (2 * a), (-b + std::sqrt(disc)) / (2 * a)}) {
    if (t > 0 && std::abs((oc + t * direction).dot(axis_)) <= half_length_) return t;
  }
  return std::nullopt;
}

double CylinderSurface::distance(const Vec3& point) const {
  const Vec3 q = point - centre_;
  return std::abs((q - q.dot(axis_) * axis_).norm() - radius_);
}

double SheetShape::height_at(double x, double y) const {
  return z0_m + slope_x * x + slope_y * y -
         sag_m * std::cos(kPi * x / width_m) * std::cos(kPi * y / height_m) +
         ripple_m * std::sin(2 * kPi * x / width_m) * std::sin(kPi * y / height_m);
}

Eigen::Vector2d SheetShape::gradient_at(double x, double y) const {
  const double ax = kPi / width_m, ay = kPi / height_m;
  return {slope_x + sag_m * ax * std::sin(ax * x) * std::cos(ay * y) +
              ripple_m * 2 * ax * std::cos(2 * ax * x) * std::sin(ay * y),
          slope_y + sag_m * ay * std::cos(ax * x) * std::sin(ay * y) +
              ripple_m * ay * std::sin(2 * ax * x) * std::cos(ay * y)};
}

SaggingSheet::SaggingSheet(SheetShape shape, Rgb rgb) : AnalyticSurface(rgb), shape_(shape) {}

std::optional<double> SaggingSheet::intersect(const Vec3& origin, const Vec3& direction) const {
  // g(t) = z(t) - f(x(t), y(t)); Newton from where the ray crosses the sheet's mean height.
  if (std::abs(direction.z()) < 1e-9) return std::nullopt;
  double t = (shape_.z0_m - 0.5 * shape_.sag_m - origin.z()) / direction.z();
  for (int it = 0; it < 30; ++it) {
    const Vec3 p = origin + t * direction;
    const double g = p.z() - shape_.height_at(p.x(), p.y());
    const double dg = direction.z() - shape_.gradient_at(p.x(), p.y()).dot(direction.head<2>());
    if (std::abs(dg) < 1e-12) return std::nullopt;
    const double step = g / dg;
    t -= step;
    if (std::abs(step) < 1e-12) break;
  }
  const Vec3 p = origin + t * direction;
  if (t <= 0 || std::abs(p.z() - shape_.height_at(p.x(), p.y())) > 1e-9) return std::nullopt;
  if (std::abs(p.x()) > 0.5 * shape_.width_m || std::abs(p.y()) > 0.5 * shape_.height_m) {
    return std::nullopt;
  }
  return t;
}

double SaggingSheet::distance(const Vec3& point) const {
  // Outside the sheet's footprint: distance to the border point; inside: first order in the
  // vertical offset (exact to O(d^2 curvature), micrometres for millimetre offsets).
  const double x = std::clamp(point.x(), -0.5 * shape_.width_m, 0.5 * shape_.width_m);
  const double y = std::clamp(point.y(), -0.5 * shape_.height_m, 0.5 * shape_.height_m);
  const double dz = point.z() - shape_.height_at(x, y);
  const double vertical = std::abs(dz) / std::sqrt(1.0 + shape_.gradient_at(x, y).squaredNorm());
  return std::hypot(std::hypot(point.x() - x, point.y() - y), vertical);
}

SurfaceMesh SaggingSheet::mesh(int cols, int rows) const {
  SurfaceMesh m = make_grid_mesh(shape_.width_m, shape_.height_m, cols, rows);
  for (Vec3& v : m.vertices_m) v.z() = shape_.height_at(v.x(), v.y());
  // z = f(x, y) over the flat grid stretches it by up to ~5 % where it slopes: the flat grid is
  // not this sheet's material, so the mesh claims no rest coordinates (registration then keeps
  // the edge lengths as given).
  m.rest_uv_m.clear();
  return m;
}

std::optional<std::pair<int, double>> Scene::cast(const Vec3& origin, const Vec3& direction) const {
  std::optional<std::pair<int, double>> best;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const std::optional<double> t = surfaces[i]->intersect(origin, direction);
    if (t && (!best || *t < best->second)) best = std::make_pair(static_cast<int>(i), *t);
  }
  return best;
}

CameraSetup look_at_camera(const std::string& name, const Vec3& position, const Vec3& target,
                           int width, int height) {
  CameraSetup c;
  c.name = name;
  const double fx = 0.5 * width / std::tan(0.5 * 65.0 * kPi / 180.0);
  c.depth = {width, height, fx, fx, 0.5 * (width - 1), 0.5 * (height - 1), 0, 0, 0, 0, 0};
  const int cw = width * 3 / 4, ch = height * 3 / 4;
  const double cfx = 0.5 * cw / std::tan(0.5 * 69.0 * kPi / 180.0);
  c.color = {cw, ch, cfx, cfx, 0.5 * (cw - 1), 0.5 * (ch - 1), 0, 0, 0, 0, 0};
  const Vec3 forward = (target - position).normalized();
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized();
  const Vec3 down = forward.cross(right);
  c.camera_to_cell.linear().col(0) = right;
  c.camera_to_cell.linear().col(1) = down;
  c.camera_to_cell.linear().col(2) = forward;
  c.camera_to_cell.translation() = position;
  // Colour camera 15 mm along the depth camera's +x: a depth-frame point is 15 mm further left
  // in the colour frame.
  c.depth_to_color.translation() = Vec3(-0.015, 0, 0);
  return c;
}

drivers::DepthFrame render_frame(const Scene& scene, const CameraSetup& camera,
                                 const NoiseModel& noise) {
  drivers::DepthFrame f;
  f.camera = camera.name;
  f.depth_intrinsics = camera.depth;
  f.color_intrinsics = camera.color;
  f.camera_to_cell = camera.camera_to_cell;
  f.depth_to_color = camera.depth_to_color;
  const drivers::Intrinsics& in = camera.depth;
  f.depth_mm.assign(static_cast<std::size_t>(in.width) * in.height, 0);
  std::mt19937 rng(noise.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Matrix3d r = camera.camera_to_cell.linear();
  const Vec3 origin = camera.camera_to_cell.translation();
  for (int v = 0; v < in.height; ++v) {
    for (int u = 0; u < in.width; ++u) {
      const double n = gauss(rng);  // drawn for every pixel: the noise does not depend on hits
      const auto hit = scene.cast(origin, r * pixel_ray(in, u, v));
      if (!hit) continue;
      const double z = hit->second;  // the ray has z = 1 in the camera frame, so t is the depth
      const double measured = z + noise.sigma_at_1m_m * z * z * n;
      const long mm = std::lround(1e3 * measured);
      if (mm > 0 && mm < 65535) f.depth_mm[static_cast<std::size_t>(v) * in.width + u] = mm;
    }
  }
  const drivers::Intrinsics& ci = camera.color;
  const Eigen::Isometry3d color_to_cell = camera.camera_to_cell * camera.depth_to_color.inverse();
  f.rgb.assign(static_cast<std::size_t>(ci.width) * ci.height * 3, 0);
  for (int v = 0; v < ci.height; ++v) {
    for (int u = 0; u < ci.width; ++u) {
      const auto hit =
          scene.cast(color_to_cell.translation(), color_to_cell.linear() * pixel_ray(ci, u, v));
      const Rgb& rgb = hit ? scene.surfaces[hit->first]->rgb() : scene.background;
      std::copy(rgb.begin(), rgb.end(), &f.rgb[3 * (static_cast<std::size_t>(v) * ci.width + u)]);
    }
  }
  return f;
}

std::vector<CameraSetup> three_cameras(int width, int height) {
  // Each camera is aimed at its own part of the sheet, so the three together see all of it and
  // any two miss some.
  return {look_at_camera("cam_front", Vec3(0.0, -1.0, 1.75), Vec3(0, -0.35, 0.8), width, height),
          look_at_camera("cam_right", Vec3(1.0, 0.6, 1.7), Vec3(0.4, 0.25, 0.8), width, height),
          look_at_camera("cam_left", Vec3(-1.0, 0.6, 1.6), Vec3(-0.4, 0.25, 0.8), width, height)};
}

Scene sheet_scene(const SheetShape& shape, std::shared_ptr<const SaggingSheet>* sheet_out) {
  Scene scene;
  auto sheet = std::make_shared<const SaggingSheet>(shape, Rgb{35, 33, 30});
  if (sheet_out) *sheet_out = sheet;
  scene.surfaces.push_back(sheet);
  scene.surfaces.push_back(std::make_shared<const PlaneSurface>(
      Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 3.0, 3.0, Rgb{170, 165, 160}));
  return scene;
}

}  // namespace tracking::testing
