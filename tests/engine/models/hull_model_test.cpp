// The hull model's predicted start (engine/README.md, "The predicted start"): the warm start
// extrapolated along the trend of the last steps saves Newton iterations and leaves the
// trajectory as it was, to the solver's tolerance.

#include "engine/models/hull_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "engine/scene_io/scene_yaml.h"
#include "engine/step_report.h"
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

// The train's first step has no warm starts, so the resting and the sliding guess make the same
// start (every contact separated, the bodies at their free-flight velocities): with a budget too
// small to solve it, the failure lists each pass at each step length with the resting guess and
// without the sliding guess, whose solve would have repeated the resting guess's iteration for
// iteration ("Restart ladder")
TEST(HullModelTest, APassNeverSolvesTwiceFromTheSameStart) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/train.yaml",
                                {"model=hull", "solver.max_iterations=2"})
                          .scene;
  State state = InitialState(scene);
  try {
    Step(scene, state);
    FAIL() << "the step solved with 2 iterations an attempt";
  } catch (const SolverFailure& e) {
    ASSERT_NE(e.step_failure(), nullptr) << e.what();
    int resting = 0;
    for (const FailedAttempt& attempt : e.step_failure()->tried) {
      EXPECT_EQ(attempt.start.rfind("sliding guess", 0), std::string::npos) << attempt.start;
      resting += attempt.start.rfind("resting guess", 0) == 0;
    }
    // 5 span lengths (the step and each first half down to h/16), each with 4 passes at usual
    // effort (the minimum-norm one too: 264 unknowns) and, once its splits failed, 2 in the
    // last resort
    EXPECT_EQ(resting, 5 * (4 + 2));
  }
}

TEST(HullModelTest, TheTrainsStrikeIsSolvedAtItsFullStep) {
  // the train's first step: the pusher strikes six boxes at rest, touching each other, whose
  // step has a set of solutions (where on each face the row's ECPs sit). The ladder's first pass
  // solves it with KLU's Newton steps (engine/README.md, "The island's linear algebra"); with
  // Eigen's SparseLU the ladder and its projected pass stalled and the minimum-norm pass solved
  // it in 286 iterations, and before that pass every pass failed at h, h/2, h/4 and h/16 and
  // the last resort solved it in 1,963)
  const Scene scene =
      LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/train.yaml", {"model=hull"}).scene;
  State state = InitialState(scene);
  // measured 42, in the warm start's pass
  constexpr int kMaxIterations = 100;
  const StepReport report = Step(scene, state);
  ASSERT_TRUE(report.converged);
  EXPECT_EQ(report.substeps, 1);
  EXPECT_LE(report.iterations, kMaxIterations);
  // m/s: the row moves on with the pusher at 0.1 m/s (measured within 4e-15 of it, the same
  // bits as the last resort's root)
  constexpr double kSpeedTolerance = 1e-12;
  for (int b = 0; b < 6; ++b) EXPECT_NEAR(state.bodies[b].v_WB.x(), 0.1, kSpeedTolerance) << b;
}

TEST(HullModelTest, AMovingIslandsWarmStartCarriesItsPointsWithItsBodies) {
  // scenes/train.yaml once the row moves with the pusher (from 1 s): every step is the last one
  // moved by h v. The last ECPs, where the bodies were, missed this step's by h v = 1 mm of 0.1
  // m boxes (the warm start's residual 1.4e-2: 9.3 Newton iterations a step); carried with their
  // bodies they solve it, verified on the residual alone (engine/README.md, "The warm start of
  // a moving island")
  const Scene scene =
      LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/train.yaml", {"model=hull"}).scene;
  State state = InitialState(scene);
  constexpr int kSettleSteps = 100, kSteps = 100;
  // measured 0 (every carried start within the tolerance); a step whose start's round-off
  // crossed it would take one iteration
  constexpr double kMeanIterations = 0.1;
  // m/s: the pusher's 0.1 m/s to the solver's tolerance
  constexpr double kSpeedTolerance = 1e-12;
  for (int i = 0; i < kSettleSteps; ++i) ASSERT_TRUE(Step(scene, state).converged);
  int iterations = 0;
  for (int i = 0; i < kSteps; ++i) {
    const StepReport report = Step(scene, state);
    ASSERT_TRUE(report.converged);
    EXPECT_EQ(report.retries, 0) << "t = " << state.t;
    iterations += report.iterations;
    for (int b = 0; b < 6; ++b)
      EXPECT_NEAR(state.bodies[b].v_WB.x(), 0.1, kSpeedTolerance) << "t = " << state.t;
  }
  EXPECT_LE(iterations, kMeanIterations * kSteps);
}

}  // namespace
}  // namespace ecpsim::engine
