// The hull model's predicted start (engine/README.md, "The predicted start"): the warm start
// extrapolated along the trend of the last steps saves Newton iterations and leaves the
// trajectory as it was, to the solver's tolerance.

#include "engine/models/hull_model.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

TEST(HullModelTest, ASlideDeceleratingUniformlyIsPredictedExactly) {
  // the paper's slide (scenes/slide.yaml): 0.5 × 0.5 × 0.1 m, 15 kg, μ = 0.22, v0 = 0.5 m/s; its
  // velocity is linear in time and its impulses constant until it stops at t* = v0 / (μ g)
  Body box = testing::MakeBoxBody(Vector3d(0.5, 0.5, 0.1), 15);
  box.p0 = Vector3d(0, 0, 0.05);
  box.v0 = Vector3d(0.5, 0, 0);
  Scene scene = testing::MakeGroundScene({box}, 0.01, Friction{0.22, 1, 1, 0.1});
  scene.model = ContactModel::kHull;
  State state = InitialState(scene);
  const double t_star = 0.5 / (0.22 * 9.8);
  // the first steps build the trend (two differences); from the fourth the predicted start is
  // the solution up to round-off, which one Newton iteration at most removes (the warm start
  // alone took 3 a step)
  constexpr int kTrendSteps = 3;
  constexpr int kRoundOffIterations = 1;
  int predicted_steps = 0;
  for (int i = 0; state.t + scene.h < t_star; ++i) {
    const StepReport report = Step(scene, state);
    ASSERT_TRUE(report.converged);
    if (i < kTrendSteps) continue;
    EXPECT_LE(report.iterations, kRoundOffIterations) << "t = " << state.t;
    EXPECT_EQ(report.retries, 0) << "t = " << state.t;
    ++predicted_steps;
  }
  EXPECT_GE(predicted_steps, 15);
}

TEST(HullModelTest, ThePredictedStartSavesAnIterationOnTheDeskAndKeepsItsAnswer) {
  // the paper's desk, flat on the ground all along: the planar sliding model's answer is the
  // hull model's (docs/paper_scenes.md, 6e-14 m/s and rad/s), and stays so from the predicted
  // start
  const Scene hull_scene = testing::PaperDeskScene(ContactModel::kHull);
  const Scene planar_scene = testing::PaperDeskScene(ContactModel::kPlanar);
  State hull = InitialState(hull_scene), planar = InitialState(planar_scene);
  // m/s, rad/s: issue 11 asks the paper's desk table unchanged to 1e-12
  constexpr double kDeskTableAgreement = 1e-12;
  // iterations a step: the warm start alone took 3.005 on average, the predicted start converges
  // in 2 where the trend is known (all but the first steps)
  constexpr double kMeanIterations = 2.05;
  double max_dv = 0, max_dw = 0;
  int iterations = 0;
  for (int i = 0; i < 400; ++i) {
    const StepReport report = Step(hull_scene, hull);
    ASSERT_TRUE(report.converged);
    ASSERT_EQ(report.retries, 0) << "t = " << hull.t;
    ASSERT_TRUE(Step(planar_scene, planar).converged);
    iterations += report.iterations;
    max_dv = std::max(max_dv, (hull.bodies[0].v_WB - planar.bodies[0].v_WB).cwiseAbs().maxCoeff());
    max_dw = std::max(max_dw, (hull.bodies[0].w_WB - planar.bodies[0].w_WB).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_dv, kDeskTableAgreement);
  EXPECT_LE(max_dw, kDeskTableAgreement);
  EXPECT_LE(iterations, kMeanIterations * 400);
}

}  // namespace
}  // namespace ecpsim::engine
