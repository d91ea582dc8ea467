#include <gtest/gtest.h>

#include "evaluation/stability_map.h"

#include <cmath>
#include <string>

#include "evaluation/method.h"
#include "tests/tolerances.h"

namespace ecpsim::evaluation {
namespace {

// a run that came to rest on a face, energy falling from 10 J
RunRecord RestedRun() {
  RunRecord run;
  run.energies = {10, 8, 5, 5};
  run.modes = {ContactMode::kNone, ContactMode::kVertex, ContactMode::kFace, ContactMode::kFace};
  run.samples.resize(4);
  return run;
}

TEST(ClassifyTest, EachOutcomeAtItsThreshold) {
  const double kinetic = 10;  // J at t = 0
  EXPECT_EQ(Classify(RestedRun(), kinetic), Outcome::kOk);

  RunRecord failed = RestedRun();
  failed.failed = true;
  EXPECT_EQ(Classify(failed, kinetic), Outcome::kSolverFailure);

  RunRecord deep = RestedRun();
  deep.max_penetration = 1.01 * kPenetrationLimit;
  EXPECT_EQ(Classify(deep, kinetic), Outcome::kPenetration);
  deep.max_penetration = 0.99 * kPenetrationLimit;
  EXPECT_EQ(Classify(deep, kinetic), Outcome::kOk);

  // a gain of 1 % of the initial kinetic energy (+ 1e-6 J) is allowed, more is not
  RunRecord gain = RestedRun();
  gain.energies[2] = 10 + kEnergyGainFraction * kinetic + 2e-6;
  EXPECT_EQ(Classify(gain, kinetic), Outcome::kEnergyGain);
  gain.energies[2] = 10 + kEnergyGainFraction * kinetic;
  EXPECT_EQ(Classify(gain, kinetic), Outcome::kOk);

  RunRecord tipped = RestedRun();
  tipped.modes.back() = ContactMode::kEdge;
  EXPECT_EQ(Classify(tipped, kinetic), Outcome::kWrongMode);

  RunRecord jitter = RestedRun();
  jitter.max_speed_late = 1.1 * kJitterSpeed;
  EXPECT_EQ(Classify(jitter, kinetic), Outcome::kJitter);
  RunRecord drift = RestedRun();
  drift.drift_late = 1.1 * kJitterDrift;
  EXPECT_EQ(Classify(drift, kinetic), Outcome::kJitter);
}

TEST(ClassifyTest, FailureOutranksAllButAnEnergyGainBeforeIt) {
  RunRecord run = RestedRun();
  run.failed = true;
  run.max_penetration = 1;
  run.drift_late = 1;
  EXPECT_EQ(Classify(run, 10), Outcome::kSolverFailure);
  // the energy grew, then the state overflowed: the gain is the cause
  run.energies[2] = 1e6;
  EXPECT_EQ(Classify(run, 10), Outcome::kEnergyGain);
}

const std::string kScenes = std::string(ECPSIM_SOURCE_DIR) + "/scenes";

TEST(StabilityMapsTest, ThrownBodiesStartJustAboveTheGround) {
  for (const StabilityMapSpec& map : StabilityMaps(kScenes)) {
    ASSERT_FALSE(map.values.empty()) << map.name;
    if (map.classify) continue;  // the push map: a box resting on the ground
    for (double value : map.values) {
      const Scenario s = map.scenario(value);
      const engine::Body& body = s.scene.bodies[0];
      double lowest = INFINITY;
      for (const Eigen::Vector3d& v : body.mesh.vertices) {
        lowest = std::min(lowest, (body.p0 + body.q0 * v).z());
      }
      constexpr double kPoseRoundOff = 1e-12;  // m: the lowest vertex placed, through a rotation
      EXPECT_NEAR(lowest, 1e-3, kPoseRoundOff) << map.name << " " << value;
      EXPECT_LT(body.v0.z(), 0) << map.name;
    }
  }
}

TEST(StabilityMapsTest, TBarMassRatioMovesItsCentreOfMassAndKeepsItsMass) {
  const StabilityMapSpec tbar = StabilityMaps(kScenes)[2];
  ASSERT_EQ(tbar.name, "tbar_mass_ratio");
  for (double ratio : tbar.values) {
    const engine::Body body = tbar.scenario(ratio).scene.bodies[0];
    EXPECT_DOUBLE_EQ(body.mass, 1);
    // the mesh is in the CM frame of the two boxes: the stem's centre is 0.05 + 0.15 = 0.2 m
    // below the bar's, m_stem = 1/(1+r), so the bar's centre (0.05 m below the top) sits
    // 0.2 m · m_stem above the CM along y
    double y_top = -INFINITY;
    for (const Eigen::Vector3d& v : body.mesh.vertices) y_top = std::max(y_top, v.y());
    constexpr double kCentreRoundOff = 1e-12;  // m: the mesh moved to the two boxes' CM
    EXPECT_NEAR(y_top - 0.05, 0.2 / (1 + ratio), kCentreRoundOff) << ratio;
    // inertia is symmetric positive definite and satisfies the triangle inequality
    const Eigen::Vector3d moments = body.inertia.diagonal();
    EXPECT_LE(moments.z(), moments.x() + moments.y() + kUnitRoundOff);
    EXPECT_NEAR(body.inertia(0, 1), 0, kUnitRoundOff);
  }
}

TEST(StabilityMapsTest, PushSpeedScalesThePushersVelocity) {
  const StabilityMapSpec push = StabilityMaps(kScenes)[3];
  ASSERT_EQ(push.name, "push_speed");
  for (double speed : push.values) {
    const Scenario s = push.scenario(speed);
    EXPECT_EQ(s.scene.bodies[s.body].name, "box");
    const engine::Body& pusher = s.scene.bodies[1 - s.body];
    ASSERT_TRUE(pusher.IsKinematic());
    const Eigen::Vector3d v = pusher.motion->StepTwist(0.3, 0.01).v;
    EXPECT_NEAR(v.x(), speed, kUnitRoundOff * speed);
    EXPECT_EQ(v.y(), 0);
    // the pusher starts where the scene file puts it
    EXPECT_EQ(pusher.motion->PoseAt(0).p, Eigen::Vector3d(-0.12, 0, 0.05));
  }
}

// a run of the push scenario at `speed` whose late samples move at `late_speed` (m/s, x)
RunRecord PushRun(const Scenario& s, double late_speed) {
  RunRecord run;
  const int samples = static_cast<int>(std::lround(s.scene.duration / s.sample_interval));
  for (int k = 0; k <= samples; ++k) {
    engine::BodyState b;
    b.v_WB.x() = k * s.sample_interval >= s.scene.duration - 0.5 ? late_speed : 0;
    run.samples.push_back(b);
  }
  return run;
}

TEST(ClassifyPushTest, OkAtThePushersSpeedOffSpeedBeyondFivePercentFailuresFirst) {
  const Scenario s = StabilityMaps(kScenes)[3].scenario(0.1);
  const Eigen::Vector3d v(0.1, 0, 0);
  EXPECT_EQ(ClassifyPush(PushRun(s, 0.1), s, v, 0.5), Outcome::kOk);
  EXPECT_EQ(ClassifyPush(PushRun(s, 0.1 * (1 + 0.9 * kPushSpeedTolerance)), s, v, 0.5),
            Outcome::kOk);
  EXPECT_EQ(ClassifyPush(PushRun(s, 0.1 * (1 + 1.1 * kPushSpeedTolerance)), s, v, 0.5),
            Outcome::kOffSpeed);
  EXPECT_EQ(ClassifyPush(PushRun(s, 0), s, v, 0.5), Outcome::kOffSpeed);  // left behind
  RunRecord deep = PushRun(s, 0.1);
  deep.max_penetration = 2 * kPenetrationLimit;
  EXPECT_EQ(ClassifyPush(deep, s, v, 0.5), Outcome::kPenetration);
  deep.failed = true;
  EXPECT_EQ(ClassifyPush(deep, s, v, 0.5), Outcome::kSolverFailure);
}

TEST(ClassifyPushTest, HullModelPushesTheBoxAtTheMapsSpeeds) {
  const StabilityMapSpec push = StabilityMaps(kScenes)[3];
  for (double speed : {push.values.front(), push.values.back()}) {
    const Scenario s = push.scenario(speed);
    const RunRecord run = RunTrajectory(FindMethod("hull"), s, 0.01, 60, 0.5);
    EXPECT_EQ(push.classify(run, s), Outcome::kOk) << speed << " m/s: " << run.failure;
  }
}

}  // namespace
}  // namespace ecpsim::evaluation
