// Registration on its own: clouds sampled straight from the analytic sheet (no cameras), so
// what is measured is the fit, not the fusion.
#include <catch2/catch.hpp>

#include <random>

#include "tests/tracking/analytic_scene.h"
#include "tracking/surface_registration.h"

namespace tracking {
namespace {

// Points on the sheet every `spacing_m`, where keep(x, y), with Gaussian noise along z.
std::vector<Eigen::Vector3f> sample_sheet(const testing::SheetShape& shape, double spacing_m,
                                          double noise_m, bool (*keep)(double, double)) {
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise_m);
  std::vector<Eigen::Vector3f> points;
  for (double x = -0.5 * shape.width_m; x <= 0.5 * shape.width_m; x += spacing_m) {
    for (double y = -0.5 * shape.height_m; y <= 0.5 * shape.height_m; y += spacing_m) {
      if (!keep(x, y)) continue;
      points.emplace_back(x, y, shape.height_at(x, y) + gauss(rng));
    }
  }
  return points;
}

bool everywhere(double, double) { return true; }
bool left_half(double x, double) { return x < 0.0; }

}  // namespace

TEST_CASE("registration moves a shifted prediction onto the cloud and reuses its analysis",
          "[tracker][registration]") {
  testing::SheetShape truth;
  truth.ripple_m = 0.02;
  const testing::SaggingSheet sheet(truth, {0, 0, 0});
  PointIndex cloud;
  cloud.build(sample_sheet(truth, 0.008, 0.002, everywhere));
  SurfaceMesh prediction = sheet.mesh(30, 25);
  for (Vec3& v : prediction.vertices_m) v.z() += 0.03;  // 3 cm too high

  SurfaceRegistration registration;
  const RegistrationResult r = registration.fit(prediction, cloud);
  REQUIRE(r.status == RegistrationStatus::kOk);
  double mean = 0.0, worst = 0.0;
  for (const Vec3& v : r.vertices_m) {
    mean += sheet.distance(v);
    worst = std::max(worst, sheet.distance(v));
  }
  mean /= r.vertices_m.size();
  CHECK(mean < 0.002);
  // Vertices move along their normals, so a vertical correction on the sheet's slopes (up to
  // 30 deg) also slides border vertices up to 1.5 cm past the edge, where the distance is to the
  // edge: the worst vertex is there.
  CHECK(worst < 0.012);
  for (std::size_t i = 0; i < r.observed.size(); ++i) {
    const Vec3& p = prediction.vertices_m[i];
    if (std::abs(p.x()) > 0.5 * truth.width_m - 0.03 ||
        std::abs(p.y()) > 0.5 * truth.height_m - 0.03) {
      continue;
    }
    CHECK(r.observed[i] == 1);
    CHECK(r.distance_to_cloud_m[i] < 0.012);
  }
  CHECK(registration.symbolic_analyses() == 1);
  registration.fit(prediction, cloud);  // same topology: the analysis is reused
  CHECK(registration.symbolic_analyses() == 1);
  registration.fit(sheet.mesh(20, 15), cloud);  // a new mesh needs a new one
  CHECK(registration.symbolic_analyses() == 2);
}

TEST_CASE("parts nobody saw follow the prediction smoothly", "[tracker][registration]") {
  testing::SheetShape truth;
  const testing::SaggingSheet sheet(truth, {0, 0, 0});
  PointIndex cloud;
  cloud.build(sample_sheet(truth, 0.008, 0.0015, left_half));
  SurfaceMesh prediction = sheet.mesh(30, 25);
  for (Vec3& v : prediction.vertices_m) v.z() += 0.02;

  SurfaceRegistration registration;
  const RegistrationResult r = registration.fit(prediction, cloud);
  REQUIRE(r.status == RegistrationStatus::kOk);
  double largest_jump = 0.0;
  for (const auto& [a, b] : unique_edges(prediction.triangles)) {
    const Vec3 da = r.vertices_m[a] - prediction.vertices_m[a];
    const Vec3 db = r.vertices_m[b] - prediction.vertices_m[b];
    largest_jump = std::max(largest_jump, (da - db).norm());
  }
  // The correction is 2 cm; vertices are 4 cm apart. A smooth displacement changes little from
  // one vertex to the next; a seen/unseen seam would jump by up to 2 cm. (Under 4 mm while unseen
  // vertices were free; 4.5 mm since they are held where they are by the data terms' weight,
  // which keeps the matrix constant and slows how fast they follow within one fit.)
  CHECK(largest_jump < 0.005);
  for (std::size_t i = 0; i < r.vertices_m.size(); ++i) {
    const double x = prediction.vertices_m[i].x(), y = prediction.vertices_m[i].y();
    // Border vertices slide along the slope past the edge (see the first test): not judged.
    const bool border =
        x < -0.5 * truth.width_m + 0.03 || std::abs(y) > 0.5 * truth.height_m - 0.03;
    if (x < -0.05 && !border) {
      CHECK(r.observed[i] == 1);
      CHECK(sheet.distance(r.vertices_m[i]) < 0.004);
    }
    if (x > 0.05) CHECK(r.observed[i] == 0);
  }
}

TEST_CASE("registration recovers a sheet from a prediction more than 10 cm off",
          "[tracker][registration]") {
  // What a clamp release can leave the twin with: it predicts the sheet flat, the sheet sags
  // 12 cm, tilts and ripples. The offset reaches 12 cm, mostly vertical, so on the slopes (up
  // to 20 deg) a normal-only correction would leave the surface centimetres off.
  testing::SheetShape truth;
  truth.slope_x = 0.04;
  truth.ripple_m = 0.015;
  const testing::SaggingSheet sheet(truth, {0, 0, 0});
  PointIndex cloud;
  cloud.build(sample_sheet(truth, 0.008, 0.002, everywhere));
  testing::SheetShape flat = truth;
  flat.sag_m = 0.0;
  flat.slope_x = 0.0;
  flat.ripple_m = 0.0;
  const SurfaceMesh prediction = testing::SaggingSheet(flat, {0, 0, 0}).mesh(30, 25);
  double before = 0.0;
  for (const Vec3& v : prediction.vertices_m) before = std::max(before, sheet.distance(v));
  CHECK(before > 0.10);

  SurfaceRegistration registration;
  const RegistrationResult r = registration.fit(prediction, cloud);
  REQUIRE(r.status == RegistrationStatus::kOk);
  double mean = 0.0, worst = 0.0;
  int seen = 0;
  for (std::size_t i = 0; i < r.vertices_m.size(); ++i) {
    if (!r.observed[i]) continue;
    const double d = sheet.distance(r.vertices_m[i]);
    mean += d;
    worst = std::max(worst, d);
    ++seen;
  }
  mean /= std::max(seen, 1);
  INFO("prediction max " << before << " m; tracked mean " << mean << " max " << worst << " over "
                         << seen << " observed of " << r.vertices_m.size() << ", iterations "
                         << r.iterations);
  CHECK(seen > 0.9 * r.vertices_m.size());
  CHECK(mean < 0.003);
  CHECK(worst < 0.012);
}

TEST_CASE("registration refuses a broken mesh or an empty cloud with a status",
          "[tracker][registration]") {
  SurfaceRegistration registration;
  PointIndex empty;
  empty.build({});
  const SurfaceMesh mesh = make_grid_mesh(1.0, 1.0, 5, 5);
  const RegistrationResult r = registration.fit(mesh, empty);
  CHECK(r.status == RegistrationStatus::kNoCloud);
  CHECK(r.vertices_m == mesh.vertices_m);
  PointIndex cloud;
  cloud.build({Eigen::Vector3f(0, 0, 0)});
  SurfaceMesh broken = mesh;
  broken.triangles[0] = Eigen::Vector3i(1, 1, 2);
  CHECK(registration.fit(broken, cloud).status == RegistrationStatus::kBadMesh);
  broken = mesh;
  broken.rest_uv_m.pop_back();
  CHECK(registration.fit(broken, cloud).status == RegistrationStatus::kBadMesh);
}

}  // namespace tracking
