// Hull-model impacts that the stability map ("impact") found unsolvable: a box thrown corner-first
// at the ground must step through to rest without a solver failure, penetration or energy gain.

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "engine/scene_io/scene_builders.h"
#include "engine/step_report.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

using Eigen::AngleAxisd;
using Eigen::Vector3d;

constexpr double kDeg = M_PI / 180;
// m: the stability map's lowest vertex above the ground at t = 0
constexpr double kStartGap = 1e-3;
// s: the stability map's run length; every case is at rest long before
constexpr double kDuration = 2.0;
// m: the solver's tolerance is 1e-12 (velocities, lengths); the mesh vertices of a box are its
// hull vertices, so a converged step leaves none deeper than round-off of the end pose
constexpr double kMaxPenetration = 1e-9;
// J: energy may only be dissipated; allow round-off of E = ½ m v² + m g z at the impact's scale
// (100 m/s: E ≈ 5e3 J, relative round-off ≈ 1e-13 per step)
constexpr double kEnergyRoundOffRel = 1e-9;
// m/s: the stability map's "late" speed bound (evaluation's kStopSpeed), |v| + |ω| × 0.13 m
constexpr double kStopSpeed = 1e-3;

// the stability map's "impact" scene (evaluation/stability_map.cpp), rebuilt on the engine alone
Scene ImpactScene(double speed, double h) {
  Body box = MakeBoxBody(Vector3d(0.2, 0.15, 0.1), 1.0);
  const Eigen::Quaterniond q(AngleAxisd(20 * kDeg, Vector3d::UnitX()) *
                             AngleAxisd(10 * kDeg, Vector3d::UnitY()));
  double lowest = INFINITY;
  for (const Vector3d& x : box.mesh.vertices) lowest = std::min(lowest, (q * x).z());
  box.q0 = q;
  box.p0 = Vector3d(0, 0, kStartGap - lowest);
  box.v0 = speed * Vector3d(0.3, 0, -1).normalized();
  Scene scene = MakeGroundScene({box}, h, Friction{0.5, 1, 1, 0.05});
  scene.duration = kDuration;
  return scene;
}

double Energy(const Scene& scene, const BodyState& b) {
  const Body& body = scene.bodies[0];
  const Eigen::Matrix3d R = b.Q_WB.toRotationMatrix();
  return 0.5 * body.mass * b.v_WB.squaredNorm() +
         0.5 * b.w_WB.dot(R * body.inertia * R.transpose() * b.w_WB) -
         body.mass * scene.gravity.dot(b.p_WB);
}

double Depth(const Scene& scene, const BodyState& b) {
  double depth = 0;
  for (const Vector3d& x : scene.bodies[0].mesh.vertices)
    depth = std::max(depth, -(b.Q_WB * x + b.p_WB).z());
  return depth;
}

struct Outcome {
  std::string failure;  // empty when the run reached kDuration
  double max_depth = 0, max_energy_gain = 0, final_speed = 0;
};

Outcome RunToRest(const Scene& scene) {
  State state = InitialState(scene);
  Outcome out;
  const double e0 = Energy(scene, state.bodies[0]);
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  for (int i = 0; i < steps; ++i) {
    try {
      Step(scene, state);
    } catch (const SolverFailure& e) {
      out.failure = e.what();
      return out;
    }
    const BodyState& b = state.bodies[0];
    out.max_depth = std::max(out.max_depth, Depth(scene, b));
    out.max_energy_gain = std::max(out.max_energy_gain, Energy(scene, b) - e0);
  }
  const BodyState& b = state.bodies[0];
  out.final_speed = b.v_WB.norm() + b.w_WB.norm() * 0.13;
  return out;
}

struct ImpactCase {
  double speed, h, tolerance;
  // whether the box must be still at 2 s: sliding friction stops a horizontal speed v_h after
  // v_h / (μ g) s at most once the box is down (10 m/s: 0.59 s; 100 m/s: 5.9 s, so not by 2 s)
  bool at_rest;
};

class ImpactRobustnessTest : public ::testing::TestWithParam<ImpactCase> {};

TEST_P(ImpactRobustnessTest, StepsThroughToRest) {
  const ImpactCase c = GetParam();
  Scene scene = ImpactScene(c.speed, c.h);
  scene.solver.tolerance = c.tolerance;
  const double e0 = Energy(scene, InitialState(scene).bodies[0]);
  const Outcome out = RunToRest(scene);
  EXPECT_EQ(out.failure, "");
  // a converged step satisfies s ≥ 0 to the solver tolerance (in m), so a looser tolerance allows
  // that much depth
  EXPECT_LE(out.max_depth, std::max(kMaxPenetration, c.tolerance));
  EXPECT_LE(out.max_energy_gain, kEnergyRoundOffRel * e0);
  // at rest after 2 s
  if (c.at_rest) {
    EXPECT_LE(out.final_speed, kStopSpeed);
  }
}

INSTANTIATE_TEST_SUITE_P(
    StabilityMapFailures, ImpactRobustnessTest,
    ::testing::Values(ImpactCase{10, 2e-4, 1e-12, true}, ImpactCase{10, 2e-4, 1e-8, true},
                      ImpactCase{10, 2e-4, 1e-5, true}, ImpactCase{1, 2e-4, 1e-12, true},
                      ImpactCase{100, 1e-2, 1e-12, false}, ImpactCase{100, 2e-2, 1e-8, false}),
    [](const ::testing::TestParamInfo<ImpactCase>& param_info) {
      const ImpactCase& c = param_info.param;
      std::string name = "speed" + std::to_string(static_cast<int>(c.speed)) + "_h" +
                         std::to_string(static_cast<int>(std::lround(c.h * 1e4))) + "e4_tol" +
                         std::to_string(static_cast<int>(std::lround(-std::log10(c.tolerance))));
      return name;
    });

}  // namespace
}  // namespace ecpsim::engine
