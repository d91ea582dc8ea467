// One solve of the hull model's island MNCP and the checks its root must pass, on small
// hand-made islands: a box at rest, a box spinning too fast for one step, a box pushed out of
// the ground, a root outside its window, and the commit of a root.

#include "engine/models/hull_attempt.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "engine/models/hull_guesses.h"
#include "engine/models/hull_tuning.h"
#include "engine/models/hull_warm_start.h"
#include "tests/engine/models/hull_islands.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

// N·s: a converged root's normal impulse against m g h = 0.196 N·s, the solver's tolerance
// (1e-12 of the residual's units) with room for the rows' conditioning
constexpr double kImpulseTolerance = 1e-12;
// m/s: a converged root's velocities of a body at rest, the same tolerance
constexpr double kVelocityTolerance = 1e-12;
// m: round-off of one position update c + h v
constexpr double kRoundOff = 1e-15;

// the island of `scene` at t = 0 with the guess `guess`, solved from it
struct Solved {
  HullIsland island;
  IslandLayout layout;
  VectorXd z;
  Attempt attempt;
  AdvanceResult result;
};

Solved SolveFrom(const Scene& scene, Guess guess, double ejection_energy) {
  Solved s{PrepareHullIsland(scene, InitialState(scene)), {}, {}, {}, {}};
  s.layout = MakeIslandLayout(s.island.problem);
  s.z =
      MakeGuess(guess, scene.gravity, s.island.problem, s.layout, s.island.local, s.island.scales);
  McpOptions options;
  options.tolerance = scene.solver.tolerance;
  options.jacobian_smoothing = kJacobianSmoothing;
  s.attempt = SolveAttempt(s.island.problem, s.layout, s.z, options, s.island.scales,
                           ejection_energy, s.island.workspace, s.result);
  return s;
}

TEST(AttemptTest, DescribeSaysWhatWasWrongWithTheRoot) {
  EXPECT_EQ((Attempt{Outcome::kAliased, 1.5e-3, 7}).Describe(),
            "aliased rotation, residual 0.0015 after 7 iterations");
  EXPECT_EQ((Attempt{Outcome::kGainsEnergy, 2e-13, 4}).Describe(),
            "energy gain, residual 2e-13 after 4 iterations");
  EXPECT_EQ((Attempt{Outcome::kUnconverged, 2.1e-9, 60}).Describe(),
            "residual 2.1e-09 after 60 iterations");
}

TEST(SolveAttemptTest, ABoxAtRestCarriesItsWeight) {
  const Solved s = SolveFrom(BoxScene(0.025), Guess::kResting, 0);
  ASSERT_EQ(s.attempt.outcome, Outcome::kSolved) << s.attempt.Describe();
  EXPECT_GT(s.attempt.iterations, 0);
  EXPECT_EQ(s.result.iterations, s.attempt.iterations);
  EXPECT_NEAR(s.z[s.layout.contacts[0].p_n], 2 * 9.8 * 0.01, kImpulseTolerance);
  EXPECT_LE(s.z.segment<3>(IslandLayout::Velocity(0)).cwiseAbs().maxCoeff(), kVelocityTolerance);
}

TEST(SolveAttemptTest, ATurnBeyondPiInOneStepIsAnAlias) {
  // high above the ground, spinning about its principal z axis at 400 rad/s: h|ω| = 4 rad
  const Solved s =
      SolveFrom(BoxScene(10, Vector3d::Zero(), Vector3d(0, 0, 400)), Guess::kSeparated, 0);
  EXPECT_EQ(s.attempt.outcome, Outcome::kAliased) << s.attempt.Describe();
  // at 300 rad/s (3 rad) the same root is a step
  const Solved slower =
      SolveFrom(BoxScene(10, Vector3d::Zero(), Vector3d(0, 0, 300)), Guess::kSeparated, 0);
  EXPECT_EQ(slower.attempt.outcome, Outcome::kSolved) << slower.attempt.Describe();
}

TEST(SolveAttemptTest, AnEjectionGainsEnergyOnlyWithinItsAllowance) {
  // 1 mm in the ground: the contact pushes the box out within the step, gaining the energy of
  // that ejection, which only EjectionEnergy's allowance admits
  const Scene scene = BoxScene(0.024);
  const Solved without = SolveFrom(scene, Guess::kResting, 0);
  EXPECT_EQ(without.attempt.outcome, Outcome::kGainsEnergy) << without.attempt.Describe();
  const HullIsland c = PrepareHullIsland(scene, InitialState(scene));
  const double allowance = EjectionEnergy(c.problem, c.local, c.scales, c.overlaps);
  const Solved with = SolveFrom(scene, Guess::kResting, allowance);
  EXPECT_EQ(with.attempt.outcome, Outcome::kSolved) << with.attempt.Describe();
}

// the box's face whose outward normal is `normal` (body frame)
int FaceAlong(const geometry::ConvexShape& hull, const Vector3d& normal) {
  for (int i = 0; i < hull.NumConstraints(); ++i)
    if (hull.Gradient(i, Vector3d::Zero()).normalized().dot(normal) > 0.5) return i;
  return -1;
}

TEST(GrowViolatedWindowsTest, ARootOutsideAFaceLeftOutGrowsTheWindowByIt) {
  Solved s = SolveFrom(BoxScene(0.025), Guess::kResting, 0);
  ASSERT_EQ(s.attempt.outcome, Outcome::kSolved);
  IslandProblem& problem = s.island.problem;
  // the root holds for the whole box
  EXPECT_FALSE(GrowViolatedWindows(problem, s.layout, s.z, s.island.scales));
  // the bottom face left out of the window, and a1 moved 5 mm below it, solved on the +x face:
  // the faces around the active one's vertices are checked, the bottom face among them
  const geometry::ConvexShape& hull = *problem.contacts[0].hull;
  std::vector<int>& window = problem.contacts[0].window;
  const int bottom = FaceAlong(hull, -Vector3d::UnitZ());
  ASSERT_GE(bottom, 0);
  window.erase(std::find(window.begin(), window.end(), bottom));
  const IslandLayout cut = MakeIslandLayout(problem);
  VectorXd z = RemapWindows(s.island.problem, s.layout, s.z, problem, cut);
  const MncpLayout::Contact& L = cut.contacts[0];
  const auto side = std::find(window.begin(), window.end(), FaceAlong(hull, Vector3d::UnitX()));
  ASSERT_NE(side, window.end());
  z.segment(L.l, L.l_count).setZero();
  z[L.l + (side - window.begin())] = 1;
  z[L.a1 + 2] -= 0.005;
  EXPECT_TRUE(GrowViolatedWindows(problem, cut, z, s.island.scales));
  EXPECT_NE(std::find(window.begin(), window.end(), bottom), window.end());
}

TEST(CommitSolutionTest, ImpulsesAreClampedAndTheBodyMovesByItsNewVelocity) {
  HullIsland c = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  const IslandLayout layout = MakeIslandLayout(c.problem);
  VectorXd z = MakeGuess(Guess::kResting, c.scene.gravity, c.problem, layout, c.local, c.scales);
  const MncpLayout::Contact& L = layout.contacts[0];
  z.segment<3>(IslandLayout::Velocity(0)) = Vector3d(0.3, 0, 0);
  z[L.p_n] = -1e-14;  // a complementarity unknown below 0 by round-off
  z[L.sigma] = 0.2;   // any σ solves a contact without a normal impulse
  const Vector3d start = c.local.bodies[0].p_WB;
  CommitSolution(c.problem, layout, z, c.local);
  EXPECT_NEAR((c.local.bodies[0].p_WB - start - c.scene.h * Vector3d(0.3, 0, 0)).norm(), 0,
              kRoundOff);
  EXPECT_EQ(c.local.bodies[0].v_WB, Vector3d(0.3, 0, 0));
  const ContactState& contact = c.local.contacts[0];
  EXPECT_EQ(contact.p_n, 0);
  EXPECT_EQ(contact.sigma, 0);
  const auto* warm = contact.warm_start.Get<HullWarmStart>();
  ASSERT_NE(warm, nullptr);
  EXPECT_EQ(warm->window, c.problem.contacts[0].window);
}

}  // namespace
}  // namespace ecpsim::engine::hull
