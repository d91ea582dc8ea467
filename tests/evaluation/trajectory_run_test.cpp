#include "evaluation/trajectory_run.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/scene_io/scene_builders.h"
#include "evaluation/error_metrics.h"
#include "evaluation/method.h"
#include "evaluation/scenario.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::AngleAxisd;
using Eigen::Vector3d;

constexpr double kG = 9.8;
// m or s: the hull model solves each step to its tolerance 1e-12, so the samples, their errors
// and the stop times are the discrete scheme's to round-off
constexpr double kSolverTolerance = 1e-12;

Scenario SlideScenario() {
  for (Scenario& s : WorkPrecisionScenarios(std::string(ECPSIM_SOURCE_DIR) + "/scenes", 0.5)) {
    if (s.name == "slide") return s;
  }
  ADD_FAILURE() << "no slide scenario";
  return {};
}

// distance slid after k steps of the implicit scheme: v_j = max(0, v0 − μ g j h), x_k = Σ h v_j
double DiscreteDistance(double v0, double mu, double h, long k) {
  double x = 0;
  for (long j = 1; j <= k; ++j) x += h * std::max(0.0, v0 - mu * kG * j * h);
  return x;
}

TEST(RunTrajectoryTest, HullSlideSamplesAreTheDiscreteSchemeAndItsErrorIsFirstOrder) {
  const Scenario slide = SlideScenario();
  const double mu = 0.3, v0 = 1;
  const Vector3d u = slide.scene.bodies[0].v0.normalized();
  double previous_error = 0;
  for (double h : {0.01, 0.002}) {
    const RunRecord run = RunTrajectory(FindMethod("hull"), slide, h);
    ASSERT_FALSE(run.failed) << run.failure;
    const int per_sample = static_cast<int>(std::lround(slide.sample_interval / h));
    ASSERT_EQ(run.samples.size(), 26u);  // 0.5 s in 0.02 s samples, plus t = 0
    double expected_error = 0;
    for (size_t k = 0; k < run.samples.size(); ++k) {
      const double x = DiscreteDistance(v0, mu, h, static_cast<long>(k) * per_sample);
      EXPECT_NEAR((run.samples[k].p_WB - slide.scene.bodies[0].p0).dot(u), x, kSolverTolerance)
          << k;
      const double t = k * slide.sample_interval;
      expected_error = std::max(
          expected_error, std::abs(x - (slide.analytic(t).p_WB - slide.scene.bodies[0].p0).dot(u)));
      EXPECT_EQ(run.modes[k], ContactMode::kFace);
    }
    const TrajectoryErrors e = CompareTrajectories(run, AnalyticTrajectory(slide), slide.length);
    EXPECT_NEAR(e.state, expected_error, kSolverTolerance);
    EXPECT_NEAR(e.position, expected_error, kSolverTolerance);
    EXPECT_EQ(e.wrong_mode, 0);
    // stopped: the first step end with v_k = max(0, v0 − μ g k h) below kStopSpeed
    long k_stop = 1;
    while (std::max(0.0, v0 - mu * kG * k_stop * h) >= kStopSpeed) ++k_stop;
    EXPECT_NEAR(run.stop_time, k_stop * h, kSolverTolerance);
    EXPECT_NEAR(e.stop_time, std::abs(k_stop * h - slide.stop_time), kSolverTolerance);
    EXPECT_LT(run.max_penetration, kSolverTolerance);
    if (previous_error > 0) {
      // first order: h five times smaller, error five times smaller (to 5 %)
      constexpr double kFirstOrderRatioTol = 0.25;  // 5 % of 5
      EXPECT_NEAR(previous_error / e.state, 5, kFirstOrderRatioTol);
    }
    previous_error = e.state;
  }
}

TEST(RunTrajectoryTest, RejectsAStepThatDoesNotDivideTheSampleInterval) {
  EXPECT_THROW(RunTrajectory(FindMethod("hull"), SlideScenario(), 0.003), InputError);
}

class ModeOfPoseTest : public ::testing::Test {
 protected:
  // a box resting on the ground at t = 0; the tests pose it
  engine::Scene scene_ = engine::MakeGroundScene({RestingBox()}, 0.01, engine::Friction{});
  static engine::Body RestingBox() {
    engine::Body box = engine::MakeBoxBody(Vector3d(0.2, 0.1, 0.05), 1);
    box.p0 = Vector3d(0, 0, 0.025);
    return box;
  }
  // the box turned by q with its lowest vertex at `gap` above z = 0
  engine::BodyState Posed(const Eigen::Quaterniond& q, double gap) {
    double lowest = INFINITY;
    for (const Vector3d& v : scene_.bodies[0].mesh.vertices) lowest = std::min(lowest, (q * v).z());
    engine::BodyState b;
    b.Q_WB = q;
    b.p_WB = Vector3d(0.3, -0.1, gap - lowest);
    return b;
  }
};

TEST_F(ModeOfPoseTest, FaceEdgeVertexAndNone) {
  const Eigen::Quaterniond flat = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond on_edge(AngleAxisd(0.2, Vector3d::UnitX()));
  const Eigen::Quaterniond on_vertex(AngleAxisd(0.2, Vector3d::UnitX()) *
                                     AngleAxisd(0.1, Vector3d::UnitY()));
  EXPECT_EQ(ModeOfPose(scene_, 0, Posed(flat, 0)), ContactMode::kFace);
  EXPECT_EQ(ModeOfPose(scene_, 0, Posed(on_edge, 0)), ContactMode::kEdge);
  EXPECT_EQ(ModeOfPose(scene_, 0, Posed(on_vertex, 0)), ContactMode::kVertex);
  // soft contacts sink a little: still touching within kContactDistance
  EXPECT_EQ(ModeOfPose(scene_, 0, Posed(flat, -0.5 * kContactDistance)), ContactMode::kFace);
  EXPECT_EQ(ModeOfPose(scene_, 0, Posed(flat, 2 * kContactDistance)), ContactMode::kNone);
  // a tilt of 1e-5 rad lifts the far edge 1e-6 m < kModeSpread: still a face
  EXPECT_EQ(
      ModeOfPose(scene_, 0, Posed(Eigen::Quaterniond(AngleAxisd(1e-5, Vector3d::UnitX())), 0)),
      ContactMode::kFace);
}

}  // namespace
}  // namespace ecpsim::evaluation
