// ODE's model of ecpsim scenes (baselines/ode_simulation.cpp) against closed forms: a box at rest,
// sliding to a stop (along an axis and diagonally), pushed below and above μ m g, a free flyer's
// pose after one step, the desk scene. Measured numbers behind each tolerance: baselines/ode.md.

#ifdef ECPSIM_HAVE_ODE

#include <cmath>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "baseline_test_scenes.h"
#include "baselines/external_simulation.h"
#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"

namespace ecpsim::baselines {
namespace {

using engine::testing::LowestVertexHeight;
using testing::BoxOnGroundScene;
using testing::DiscreteStopDistance;
using testing::kBoxMass;
using testing::kClockRoundOff;
using testing::kG;
using testing::kNonDiagonalInertia;
using testing::kSlideMu;
using testing::kStopShortfall;
using testing::kStopShortfallTolerance;

/// Bound on a resting or sliding box's sinking and drift over 100 steps, m: ODE's default global
/// CFM (1e-10 in double precision) lets a contact give by CFM × its force, measured 1.2e-11 m.
constexpr double kRestTolerance = 1e-9;
/// m, m/s: kCoulomb's Dantzig LCP solves each step exactly, so the closed forms of the
/// semi-implicit Euler motion hold to round-off
constexpr double kCoulombTolerance = 1e-9;
/// m, rad, m/s, rad/s: one free-flight step, p += h v⁺ in ODE and ecpsim alike (and with
/// kCoulomb's finite rotation mode Q⁺ = Exp(h ω) Q), agrees to round-off
constexpr double kFreeFlightTolerance = 1e-9;

std::unique_ptr<ExternalSimulation> RunOde(FrictionSetting setting, const engine::Scene& scene,
                                           int steps) {
  auto sim = MakeExternalSimulation(ExternalEngine::kOde, setting, scene);
  for (int i = 0; i < steps; ++i) sim->Step();
  return sim;
}

// m: QuickStep's 20 Gauss–Seidel sweeps leave a residual in a slide's stop distance that depends
// on the order of the contacts; 1e-3 m is 0.6 % of the 0.165 m slide, far below the difference
// between the pyramid and the cone that the tests tell apart (30 %)
constexpr double kQuickStepResidual = 1e-3;

TEST(OdeSimulation, CoulombBoxRestsOnThePlaneWithoutDrift) {
  const engine::Scene scene = BoxOnGroundScene();
  const auto sim = RunOde(FrictionSetting::kCoulomb, scene, 100);
  const engine::BodyState& box = sim->state().bodies[0];
  EXPECT_NEAR(sim->state().t, 1.0, kClockRoundOff);
  EXPECT_LT((box.p_WB - scene.bodies[0].p0).norm(), kRestTolerance);
  EXPECT_NEAR(LowestVertexHeight(scene.bodies[0], box), 0, kRestTolerance);
  EXPECT_LT(box.v_WB.norm(), kRestTolerance);
}

TEST(OdeSimulation, SlidingBoxStopsAtTheDiscreteCoulombDistance) {
  const engine::Scene scene = BoxOnGroundScene(Eigen::Vector3d(1, 0, 0));
  const double discrete = DiscreteStopDistance(1, kSlideMu, kG, scene.h);
  const double continuous = 1 / (2 * kSlideMu * kG);
  // sliding along a friction direction of ODE's pyramid: μ λ_n every step, the semi-implicit
  // Euler stop distance; Dantzig (kCoulomb) to round-off, kDefault's 20 QuickStep sweeps to
  // their Gauss–Seidel residual, which depends on the order of the box's four contacts (the
  // hull's vertex order: 3.8e-7 m and 1.4e-4 m long for two orders, 1.8e-4 m sideways)
  const auto coulomb = RunOde(FrictionSetting::kCoulomb, scene, 100);
  EXPECT_NEAR(coulomb->state().bodies[0].p_WB.x(), discrete, kCoulombTolerance);
  EXPECT_NEAR(coulomb->state().bodies[0].p_WB.y(), 0, kRestTolerance);
  const auto quick = RunOde(FrictionSetting::kDefault, scene, 100);
  EXPECT_NEAR(quick->state().bodies[0].p_WB.x(), discrete, kQuickStepResidual);
  EXPECT_NEAR(quick->state().bodies[0].p_WB.y(), 0, kQuickStepResidual);
  // which is v0 h/2 = 5 mm (2.9 %) short of the continuous v0²/(2μg)
  EXPECT_NEAR(coulomb->state().bodies[0].p_WB.x() / continuous - 1, kStopShortfall,
              kStopShortfallTolerance);
}

TEST(OdeSimulation, DiagonalSlideFeelsTheConeWithCoulombAndThePyramidWithDefault) {
  // v0 at 45° to ODE's friction directions: kCoulomb's friction along the slip gives the Coulomb
  // stop distance; kDefault's pyramid resists each axis with μ λ_n, √2 μ λ_n in all, and stops
  // the box after 1/√2 of it (the discrete sums differ slightly from exactly 1/√2), up to
  // QuickStep's residual (measured 2.6e-6 m and 1.8e-4 m for two orders of the contacts)
  const Eigen::Vector3d v0 = Eigen::Vector3d(1, 1, 0) / std::sqrt(2.0);
  const engine::Scene scene = BoxOnGroundScene(v0);
  const auto coulomb = RunOde(FrictionSetting::kCoulomb, scene, 100);
  // m: the friction directions turned by 45°, the exact solve's round-off with room
  constexpr double kDiagonalCoulombTolerance = 1e-8;
  EXPECT_NEAR(coulomb->state().bodies[0].p_WB.head<2>().norm(),
              DiscreteStopDistance(1, kSlideMu, kG, scene.h), kDiagonalCoulombTolerance);
  const auto pyramid = RunOde(FrictionSetting::kDefault, scene, 100);
  EXPECT_NEAR(pyramid->state().bodies[0].p_WB.head<2>().norm(),
              std::sqrt(2.0) * DiscreteStopDistance(1 / std::sqrt(2.0), kSlideMu, kG, scene.h),
              kQuickStepResidual);
}

TEST(OdeSimulation, CoulombBoxPushedBelowSlidingFrictionStays) {
  engine::Scene scene = BoxOnGroundScene();
  engine::Load push;
  push.x = engine::TimeFunction(0.5 * kSlideMu * kBoxMass * kG);
  scene.loads.push_back(push);
  const auto sim = RunOde(FrictionSetting::kCoulomb, scene, 100);
  EXPECT_LT((sim->state().bodies[0].p_WB - scene.bodies[0].p0).norm(), kRestTolerance);
}

TEST(OdeSimulation, CoulombBoxPushedAboveSlidingFrictionAcceleratesAtTheCoulombRate) {
  // F = 1.1 μ m g: a = 0.1 μ g; semi-implicit Euler after N steps: v = N a h,
  // x = a h² N (N + 1)/2
  engine::Scene scene = BoxOnGroundScene();
  engine::Load push;
  push.x = engine::TimeFunction(1.1 * kSlideMu * kBoxMass * kG);
  scene.loads.push_back(push);
  const int n = 100;
  const auto sim = RunOde(FrictionSetting::kCoulomb, scene, n);
  const double a = 0.1 * kSlideMu * kG;
  const engine::BodyState& box = sim->state().bodies[0];
  EXPECT_NEAR(box.v_WB.x(), n * a * scene.h, kCoulombTolerance);
  EXPECT_NEAR(box.p_WB.x(), a * scene.h * scene.h * n * (n + 1) / 2, kCoulombTolerance);
}

TEST(OdeSimulation, FreeFlightMatchesEcpsimsBodyFrameAfterOneStep) {
  // a non-diagonal inertia, turned q0, ω0 along a principal axis: p += h v⁺ in both; kCoulomb's
  // finite rotation mode turns Q by Exp(h ω) like ecpsim
  const engine::Scene scene = testing::FreeFlightScene();
  ASSERT_GT(scene.bodies[0].inertia(0, 1) * scene.bodies[0].inertia(0, 1), kNonDiagonalInertia);
  engine::State expected = engine::InitialState(scene);
  engine::Step(scene, expected);
  const engine::BodyState& want = expected.bodies[0];
  for (FrictionSetting setting : {FrictionSetting::kDefault, FrictionSetting::kCoulomb}) {
    const auto sim = RunOde(setting, scene, 1);
    const engine::BodyState& actual = sim->state().bodies[0];
    EXPECT_NEAR(sim->state().t, expected.t, kUnitRoundOff);
    EXPECT_LT((actual.p_WB - want.p_WB).norm(), kFreeFlightTolerance);
    EXPECT_LT((actual.v_WB - want.v_WB).norm(), kFreeFlightTolerance);
    EXPECT_LT((actual.w_WB - want.w_WB).norm(), kFreeFlightTolerance);
    if (setting == FrictionSetting::kCoulomb) {
      EXPECT_LT(actual.Q_WB.angularDistance(want.Q_WB), kFreeFlightTolerance);
    } else {
      // ODE's default first-order update normalize(1, h ω/2) ⊗ Q turns by 2 atan(h|ω|/2)
      // instead of h|ω|: short by (h|ω|)³/12 = 2.8e-7 rad here
      const double turn = scene.h * scene.bodies[0].w0.norm();
      constexpr double kTurnRoundOff = 1e-12;  // rad: round-off of the two 0.015 rad turns
      EXPECT_NEAR(actual.Q_WB.angularDistance(want.Q_WB), turn - 2 * std::atan(turn / 2),
                  kTurnRoundOff);
    }
  }
}

TEST(OdeSimulation, DeskSceneRunsHalfASecondWithBothSettings) {
  const engine::Scene scene = engine::LoadScene(ECPSIM_SOURCE_DIR "/scenes/desk.yaml").scene;
  for (FrictionSetting setting : {FrictionSetting::kDefault, FrictionSetting::kCoulomb}) {
    const auto sim = RunOde(setting, scene, 50);
    EXPECT_NEAR(sim->state().t, 0.5, kClockRoundOff);
    EXPECT_TRUE(testing::StateFinite(sim->state()));
    // the desk slides without tipping: its CM stays 0.45 m up (QuickStep lets it sink ~1 mm)
    constexpr double kQuickStepSink = 2e-3;  // m
    EXPECT_NEAR(sim->state().bodies[0].p_WB.z(), 0.45, kQuickStepSink);
  }
}

TEST(OdeSimulation, RejectsAnObstacleThatIsNotAHalfSpace) {
  engine::Scene scene = BoxOnGroundScene();
  scene.obstacles[0].name = "fixture";
  scene.obstacles[0].shape = geometry::MakeBox(Eigen::Vector3d(1, 1, 0.1));
  EXPECT_THAT(
      [&] { MakeExternalSimulation(ExternalEngine::kOde, FrictionSetting::kDefault, scene); },
      ::testing::ThrowsMessage<InputError>(::testing::AllOf(
          ::testing::HasSubstr("fixture"), ::testing::HasSubstr("half-spaces only"))));
}

TEST(OdeSimulation, AnInternalErrorOfOdeIsASolverFailureNotAnAbort) {
  // an infinite spin makes ODE's orientation update NaN: its quaternion normalization
  // fails an internal assertion, which would abort the process (a whole benchmark with it)
  engine::Scene scene = BoxOnGroundScene();
  scene.bodies[0].p0.z() = 10;  // far from the ground: free flight
  scene.bodies[0].w0 = Eigen::Vector3d(INFINITY, 0, 0);
  auto sim = MakeExternalSimulation(ExternalEngine::kOde, FrictionSetting::kCoulomb, scene);
  EXPECT_THAT([&] { sim->Step(); },
              ::testing::ThrowsMessage<engine::SolverFailure>(::testing::AllOf(
                  ::testing::HasSubstr("ODE internal error"), ::testing::HasSubstr("t = 0 s"))));
}

}  // namespace
}  // namespace ecpsim::baselines

#endif  // ECPSIM_HAVE_ODE
