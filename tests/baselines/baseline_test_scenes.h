#pragma once
// Scenes with closed-form outcomes for the external engines' tests (Bullet, ODE): a box resting,
// sliding and pushed on the ground, and a free flyer with a non-diagonal inertia.

#include <cmath>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "../engine/test_bodies.h"
#include "baselines/external_simulation.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/paper_bodies.h"
#include "tests/tolerances.h"

namespace ecpsim::baselines::testing {

/// The test box: 0.2 × 0.2 × 0.1 m, 1 kg, lying on its large face on z = 0.
inline const Eigen::Vector3d kBoxSize(0.2, 0.2, 0.1);  // m
constexpr double kBoxMass = 1;                         // kg
constexpr double kSlideMu = 0.3;                       // the sliding tests' μ
constexpr double kG = 9.8;                             // m/s², the scenes' |g|

/// s: an engine's clock sums h = 0.01 s over ≤ 100 steps, a few ulps each
constexpr double kClockRoundOff = 1e-12;

/// The box on the ground with μ = kSlideMu, at rest unless `v0` (m/s, world) is given.
inline engine::Scene BoxOnGroundScene(const Eigen::Vector3d& v0 = Eigen::Vector3d::Zero()) {
  engine::Body box = engine::testing::MakeBoxBody(kBoxSize, kBoxMass);
  box.p0 = Eigen::Vector3d(0, 0, kBoxSize.z() / 2);
  box.v0 = v0;
  return engine::testing::MakeGroundScene({box}, 0.01, engine::Friction{kSlideMu, 1, 1, 0.1});
}

/// Distance a block sliding at v0 on flat ground covers before stopping under Coulomb friction
/// μ g, integrated as every engine here does (semi-implicit Euler: v_{k+1} = v_k − μ g h,
/// x_{k+1} = x_k + h v_{k+1}, until v reaches 0): v0²/(2μg) − v0 h/2 up to the last partial step,
/// 3 % less than the continuous v0²/(2μg) for v0 = 1 m/s, μ = 0.3, h = 0.01 s.
inline double DiscreteStopDistance(double v0, double mu, double g, double h) {
  double v = v0;
  double x = 0;
  while (v > 0) {
    v = std::max(0.0, v - mu * g * h);
    x += h * v;
  }
  return x;
}

/// That shortfall, x/(v0²/(2μg)) − 1 ≈ −h μ g / v0 = −0.0294 for v0 = 1 m/s, to the 0.001 that
/// the last partial step and the rounding of −0.0294 leave.
constexpr double kStopShortfall = -0.0294;
constexpr double kStopShortfallTolerance = 0.001;

/// A free flyer 10 m above the ground (never touching it in one step): a box mesh turned inside
/// its body frame, so its inertia is not diagonal; q0 turned, w0 along the world image of one of
/// its principal axes (so ω stays constant and the gyroscopic term vanishes in every engine) and
/// v0 oblique.
inline engine::Scene FreeFlightScene() {
  geometry::TriangleMesh mesh = geometry::MakeBox(Eigen::Vector3d(0.15, 0.1, 0.05))->Tessellate();
  const Eigen::Matrix3d R_mesh =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (auto& v : mesh.vertices) v = R_mesh * v;
  engine::Body body = engine::testing::MakeMeshBody(mesh, 2.0, "flyer");
  body.p0 = Eigen::Vector3d(0.1, -0.2, 10);
  body.q0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(-1, 1, 2).normalized()));
  // the box's first edge axis is a principal axis of the turned mesh
  body.w0 = 1.5 * (body.q0 * (R_mesh * Eigen::Vector3d::UnitX()));
  body.v0 = Eigen::Vector3d(0.3, -0.1, 0.5);
  return engine::testing::MakeGroundScene({body}, 0.01);
}

/// kg²·m⁴: the free flyer's I_xy² exceeds this, far above round-off: its inertia is not diagonal.
constexpr double kNonDiagonalInertia = 1e-8;

/// Whether every body's pose and velocity are finite.
inline bool StateFinite(const engine::State& state) {
  for (const auto& b : state.bodies) {
    if (!b.p_WB.allFinite() || !b.Q_WB.coeffs().allFinite() || !b.v_WB.allFinite() ||
        !b.w_WB.allFinite()) {
      return false;
    }
  }
  return true;
}

}  // namespace ecpsim::baselines::testing
