#include <gtest/gtest.h>

#include "evaluation/stability_map.h"

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

TEST(StabilityMapsTest, BodiesStartJustAboveTheGround) {
  for (const StabilityMapSpec& map : StabilityMaps()) {
    ASSERT_FALSE(map.values.empty()) << map.name;
    for (double value : map.values) {
      const Scenario s = map.scenario(value);
      const engine::Body& body = s.scene.bodies[0];
      double lowest = INFINITY;
      for (const Eigen::Vector3d& v : body.mesh.vertices) {
        lowest = std::min(lowest, (body.p0 + body.q0 * v).z());
      }
      EXPECT_NEAR(lowest, 1e-3, 1e-12) << map.name << " " << value;
      EXPECT_LT(body.v0.z(), 0) << map.name;
    }
  }
}

TEST(StabilityMapsTest, TBarMassRatioMovesItsCentreOfMassAndKeepsItsMass) {
  const StabilityMapSpec tbar = StabilityMaps()[2];
  ASSERT_EQ(tbar.name, "tbar_mass_ratio");
  for (double ratio : tbar.values) {
    const engine::Body body = tbar.scenario(ratio).scene.bodies[0];
    EXPECT_DOUBLE_EQ(body.mass, 1);
    // the mesh is in the CM frame of the two boxes: the stem's centre is 0.05 + 0.15 = 0.2 m
    // below the bar's, m_stem = 1/(1+r), so the bar's centre (0.05 m below the top) sits
    // 0.2 m · m_stem above the CM along y
    double y_top = -INFINITY;
    for (const Eigen::Vector3d& v : body.mesh.vertices) y_top = std::max(y_top, v.y());
    EXPECT_NEAR(y_top - 0.05, 0.2 / (1 + ratio), 1e-12) << ratio;
    // inertia is symmetric positive definite and satisfies the triangle inequality
    const Eigen::Vector3d moments = body.inertia.diagonal();
    EXPECT_LE(moments.z(), moments.x() + moments.y() + 1e-15);
    EXPECT_NEAR(body.inertia(0, 1), 0, 1e-15);
  }
}

}  // namespace
}  // namespace ecpsim::evaluation
