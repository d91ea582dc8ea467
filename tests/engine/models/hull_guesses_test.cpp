// The hull model's starts on small hand-made islands: the ladder's order, the stall budgets,
// free flight in closed form, landings, and the resting guess's impulse.

#include "engine/models/hull_guesses.h"

#include <cmath>

#include <gtest/gtest.h>

#include "engine/models/hull_tuning.h"
#include "engine/models/hull_warm_start.h"
#include "engine/time_step.h"
#include "tests/engine/models/hull_islands.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

// m, N·s: round-off of the few operations between the closed forms and the code
constexpr double kRoundOff = 1e-15;

TEST(StallIterationsTest, EachGuessHasItsBudget) {
  EXPECT_EQ(StallIterations(Guess::kPredicted, true, false, 1), kPredictedStallIterations);
  EXPECT_EQ(StallIterations(Guess::kWarm, true, false, 1), kWarmStartStallIterations);
  // a warm start of several bodies, or in a later pass, has the full budget
  EXPECT_EQ(StallIterations(Guess::kWarm, true, false, 2), kStallIterations);
  EXPECT_EQ(StallIterations(Guess::kWarm, false, false, 1), kStallIterations);
  EXPECT_EQ(StallIterations(Guess::kSliding, true, false, 1), kStallIterations);
  // the plain Newton iteration of the last resort never gives up early
  EXPECT_EQ(StallIterations(Guess::kPredicted, false, true, 1), 0);
}

TEST(MayFlyFreeTest, ABodyHighAboveTheGroundFliesFreeAndOneOnItDoesNot) {
  const HullIsland high = PrepareHullIsland(BoxScene(1), InitialState(BoxScene(1)));
  EXPECT_TRUE(MayFlyFree(high.problem, high.local));
  IslandProblem problem = high.problem;
  const IslandLayout layout = MakeIslandLayout(problem);
  const VectorXd z =
      MakeGuess(Guess::kSeparated, high.scene.gravity, problem, layout, high.local, high.scales);
  EXPECT_TRUE(AllContactsApart(problem, layout, z, high.local));
  // the separated guess is free flight: v + g h, no impulse
  EXPECT_NEAR(z[IslandLayout::Velocity(0) + 2], -9.8 * high.scene.h, kRoundOff);
  EXPECT_EQ(z[layout.contacts[0].p_n], 0);

  const HullIsland resting = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  EXPECT_FALSE(MayFlyFree(resting.problem, resting.local));
}

TEST(MakeGuessTest, TheRestingGuessCancelsTheApproachAndGravityUnderTheCentre) {
  const HullIsland c = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  IslandProblem problem = c.problem;
  const IslandLayout layout = MakeIslandLayout(problem);
  const VectorXd z =
      MakeGuess(Guess::kResting, c.scene.gravity, problem, layout, c.local, c.scales);
  const MncpLayout::Contact& L = layout.contacts[0];
  // the free flight's approach m g h and the step's weight m g h
  EXPECT_NEAR(z[L.p_n], 2 * 2 * 9.8 * c.scene.h, kRoundOff);
  EXPECT_EQ(z.segment<3>(IslandLayout::Velocity(0)), Vector3d::Zero());
  // a1 under the centre of mass, on the bottom face at the free-flight end pose
  EXPECT_EQ(z[L.a1], 0);
  EXPECT_EQ(z[L.a1 + 1], 0);
  EXPECT_NEAR(z[L.a1 + 2], -9.8 * c.scene.h * c.scene.h, kRoundOff);
}

// a box resting on its +x bottom edge, tilted by `tilt` about y, turning about that edge at
// `w_y` (negative: falling flat), its last contact at the edge's midpoint with a normal impulse
HullIsland TiltedBoxOnItsEdge(double tilt, double w_y) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(tilt, Vector3d::UnitY()));
  const Vector3d c(0, 0, 0.1 * std::sin(tilt) + 0.025 * std::cos(tilt));
  const Vector3d a1 = c + q * Vector3d(0.1, 0, -0.025);
  const Vector3d w(0, w_y, 0);
  const Scene scene = BoxScene(c.z(), w.cross(c - a1), w, q);
  State state = InitialState(scene);
  state.contacts[0].p_n = 0.1;
  state.contacts[0].a1 = a1;
  state.contacts[0].warm_start.Set(HullWarmStart{});
  return PrepareHullIsland(scene, state);
}

TEST(LandsTest, ABoxFallingFlatWithinTheStepLands) {
  // tilted 0.05 rad and turning 10 rad/s: the step's turn of 0.1 rad takes its other bottom edge
  // 0.2 sin(0.05) m under the ground, far beyond kLandingDip of its length
  const HullIsland falling = TiltedBoxOnItsEdge(0.05, -10);
  EXPECT_TRUE(Lands(falling.problem, falling.local, falling.scales));
  EXPECT_TRUE(AnyBodyMoving(falling.local, falling.scales));
  const GuessLadder sliding_first = {Guess::kSliding, Guess::kWarm, Guess::kResting,
                                     Guess::kSeparated};
  EXPECT_EQ(HullLadder(falling.problem, falling.local, falling.scales, true), sliding_first);
  // at 2 rad/s it turns 0.02 rad about the edge it rests on: still rocking on it
  const HullIsland rocking = TiltedBoxOnItsEdge(0.05, -2);
  EXPECT_FALSE(Lands(rocking.problem, rocking.local, rocking.scales));
  const GuessLadder warm_first = {Guess::kWarm, Guess::kSliding, Guess::kResting,
                                  Guess::kSeparated};
  EXPECT_EQ(HullLadder(rocking.problem, rocking.local, rocking.scales, true), warm_first);
}

TEST(HullLadderTest, ASlideAlongItsTrendStartsFromThePrediction) {
  // sliding at 0.5 m/s: after three hull steps the trend of its solution is known
  Scene scene = BoxScene(0.025, Vector3d(0.5, 0, 0));
  State state = InitialState(scene);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(Step(scene, state).converged);
  const HullIsland c = PrepareHullIsland(scene, state);
  ASSERT_TRUE(AnyBodyMoving(c.local, c.scales));
  EXPECT_TRUE(Predictable(c.problem, c.local, c.scales));
  const GuessLadder predicted_first = {Guess::kPredicted, Guess::kWarm, Guess::kSliding,
                                       Guess::kResting, Guess::kSeparated};
  EXPECT_EQ(HullLadder(c.problem, c.local, c.scales, true), predicted_first);
}

TEST(HullLadderTest, ABoxAtRestStartsFromItsWarmStart) {
  Scene scene = BoxScene(0.025);
  State state = InitialState(scene);
  for (int i = 0; i < 2; ++i) ASSERT_TRUE(Step(scene, state).converged);
  const HullIsland c = PrepareHullIsland(scene, state);
  ASSERT_FALSE(AnyBodyMoving(c.local, c.scales));
  const GuessLadder warm_first = {Guess::kWarm, Guess::kResting, Guess::kSliding,
                                  Guess::kSeparated};
  EXPECT_EQ(HullLadder(c.problem, c.local, c.scales, false), warm_first);
}

}  // namespace
}  // namespace ecpsim::engine::hull
