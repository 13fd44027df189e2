// Damped dynamics: a sheet hanging from two clamps, released flat, swings under gravity.
// With the clamps still, nothing does work on the sheet, and backward Euler with strain-rate
// viscosity only removes energy: E = kinetic + membrane + bending + gravity must not rise from
// one step to the next and must fall clearly over the swing. With a clamp moving along a
// prescribed path every step must still be usable and the clamp must be where it was sent.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <utility>

#include "twin/solvers/implicit_stepper.h"

namespace twin::dynamics_test {
namespace {

constexpr double kWidth_m = 0.4, kHeight_m = 0.3, kStep_s = 0.01;

Material viscous_material() {
  Material m;  // 0.3 kg/m^2, 5000 N/m, 1e-3 N*m
  m.tensile_viscosity_Ns_m = 2.0;
  m.shear_viscosity_Ns_m = 2.0;
  return m;
}

double total_energy_J(const ShellModel& model, const VecX& x, const VecX& v) {
  double e = kinetic_energy(model, v);
  for (const EnergyTerm* term : model.potential_terms()) {
    e += term->evaluate(x, nullptr, nullptr, HessianMode::kExact);
  }
  return e;
}

struct Rig {
  ShellModel model{make_rectangular_sheet(kWidth_m, kHeight_m, 0.04), viscous_material()};
  ClampSet clamps{model.mesh(), {{"left", Vec2(0.06, 0.26), 0.03}, {"right", Vec2(0.34, 0.26), 0.03}}};
  SheetPlacement placement{Vec3(0.0, 0.0, 1.0), Mat3::Identity()};  // flat at z = 1 m
  std::vector<ClampPose> poses;
  VecX x = place_flat(model.mesh(), placement);
  VecX v = VecX::Zero(x.size());
  Rig() {
    for (int i = 0; i < clamps.size(); ++i) {
      poses.push_back({placement.to_world(clamps[i].spec().material_point_m), Mat3::Identity(), true});
    }
  }
};

TEST_CASE("a released sheet swinging on still clamps loses energy", "[twin][physics]") {
  Rig rig;
  ImplicitStepper stepper(rig.model);
  // Energy unit: the sheet's weight times its size (J), independent of where z = 0 is.
  const double scale_J = rig.model.total_mass_kg() * kStandardGravity * std::hypot(kWidth_m, kHeight_m);
  const double start_J = total_energy_J(rig.model, rig.x, rig.v);
  double previous_J = start_J, lowest_z = 1.0, largest_speed = 0.0;
  for (int step = 0; step < 50; ++step) {
    const SolveReport report = stepper.step(rig.x, rig.v, kStep_s, rig.clamps, rig.poses);
    INFO("step " << step << ": " << report.brief());
    REQUIRE(report.usable());
    const double energy_J = total_energy_J(rig.model, rig.x, rig.v);
    INFO("energy " << energy_J << " J after " << previous_J << " J");
    CHECK(energy_J <= previous_J + 1e-9 * scale_J);
    previous_J = energy_J;
    for (int i = 0; i < rig.model.vertex_count(); ++i) {
      lowest_z = std::min(lowest_z, rig.x(3 * i + 2));
      largest_speed = std::max(largest_speed, vertex(rig.v, i).norm());
    }
  }
  // It really swung: the free edge fell well over 10 cm and moved at over 1 m/s
  // (free fall over 0.2 m reaches 2 m/s).
  CHECK(lowest_z < 0.85);
  CHECK(largest_speed > 1.0);
  // Viscosity and the scheme took a clear share of the energy released by the fall.
  CHECK(previous_J < start_J - 0.05 * scale_J);
}

// Moves the right clamp along path(t) (position offset, m, and rotation) for 50 steps of
// 10 ms; every step must be usable and the held vertices must be exactly where sent.
template <class Path>
void follow_path(const Path& path) {
  Rig rig;
  ImplicitStepper stepper(rig.model);
  const int right = rig.clamps.index_of("right");
  const Vec3 start = rig.poses[right].position_m;
  const Clamp& clamp = rig.clamps[right];
  for (int step = 1; step <= 50; ++step) {
    const std::pair<Vec3, Mat3> pose = path(step * kStep_s);
    const Mat3& rotation = pose.second;
    rig.poses[right].position_m = start + pose.first;
    rig.poses[right].rotation = rotation;
    const SolveReport report = stepper.step(rig.x, rig.v, kStep_s, rig.clamps, rig.poses);
    INFO("step " << step << ": " << report.brief());
    REQUIRE(report.usable());
    REQUIRE(rig.x.allFinite());
    for (int vtx : clamp.vertices()) {
      const Vec2 uv = rig.model.mesh().rest_uv[vtx] - clamp.spec().material_point_m;
      const Vec3 held = rig.poses[right].position_m + rotation.leftCols<2>() * uv;
      CHECK((vertex(rig.x, vtx) - held).norm() < 1e-12);
    }
  }
}

// Smooth start and stop: 0 -> 1 over 0.5 s with zero speed at both ends.
double ramp(double t_s) { return 0.5 * (1.0 - std::cos(M_PI * std::min(1.0, t_s / 0.5))); }

TEST_CASE("every step is usable while a clamp lifts, pulls and turns the sheet",
          "[twin][physics]") {
  // 10 cm outwards, 5 cm up, 0.3 rad about y, as a robot would move it (peak 0.18 m/s).
  follow_path([](double t_s) {
    const double s = ramp(t_s);
    return std::make_pair(Vec3(0.1 * s, 0.0, 0.05 * s),
                          Mat3(Eigen::AngleAxisd(0.3 * s, Vec3::UnitY()).toRotationMatrix()));
  });
}

// Pushing the flat sheet into compression makes the step's exact Hessian indefinite (the sheet
// buckles); the stepper must still deliver every step (it sub-steps when Newton stalls).
TEST_CASE("every step is usable while a clamp moves towards the other one", "[twin][physics]") {
  follow_path([](double t_s) {
    return std::make_pair(Vec3(-0.1 * ramp(t_s), 0.0, 0.05 * ramp(t_s)), Mat3(Mat3::Identity()));
  });
}

// A clamp that starts at full speed, 0.1 m circle in 0.5 s (1.26 m/s) while turning. On the first
// call the stepper must move the clamp from where its material point is, not hold it at the end
// pose in every sub-step (it did, and step 1 failed even with 8 sub-steps).
TEST_CASE("the first step is usable when a clamp starts at full speed",
          "[twin][physics]") {
  follow_path([](double t_s) {
    const double phase = 2.0 * M_PI * t_s / 0.5;
    return std::make_pair(Vec3(0.1 * std::sin(phase), 0.0, 0.1 * (1.0 - std::cos(phase))),
                          Mat3(Eigen::AngleAxisd(0.3 * std::sin(phase), Vec3::UnitY()).toRotationMatrix()));
  });
}

}  // namespace
}  // namespace twin::dynamics_test
