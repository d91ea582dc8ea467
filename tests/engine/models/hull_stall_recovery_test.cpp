// The hull model's re-solves of a stall on small hand-made islands: which stalls are re-solved,
// which faces carry a contact, which contact stalled, and each re-solve from an iterate whose
// multipliers spread over more faces than carry the contact.

#include "engine/models/hull_stall_recovery.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "engine/models/hull_guesses.h"
#include "engine/models/hull_tuning.h"
#include "geometry/triangle_mesh.h"
#include "tests/engine/models/hull_islands.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

// N·s: a committed root's normal impulse against m g h = 0.196 N·s, the solver's tolerance
// (1e-12 of the residual's units)
constexpr double kImpulseTolerance = 1e-12;

TEST(IsNearSolutionStallTest, ABodyAloneIsReSolvedFartherFromTheTolerance) {
  const double tolerance = 1e-12;
  const HullIsland box = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  const IslandLayout one = MakeIslandLayout(box.problem);
  EXPECT_TRUE(IsNearSolutionStall(one, {Outcome::kUnconverged, kMaxOneBodyStall * tolerance, 9},
                                  tolerance));
  EXPECT_FALSE(IsNearSolutionStall(
      one, {Outcome::kUnconverged, 2 * kMaxOneBodyStall * tolerance, 9}, tolerance));
  const HullIsland stack = PrepareHullIsland(StackScene(), InitialState(StackScene()));
  const IslandLayout two = MakeIslandLayout(stack.problem);
  EXPECT_TRUE(IsNearSolutionStall(two, {Outcome::kUnconverged, kMaxDegenerateStall * tolerance, 9},
                                  tolerance));
  EXPECT_FALSE(IsNearSolutionStall(
      two, {Outcome::kUnconverged, 2 * kMaxDegenerateStall * tolerance, 9}, tolerance));
}

TEST(CarryingTest, FacesAboveAMillionthOfTheLargestCarry) {
  const VectorXd z = (VectorXd(6) << 7, 1, 1e-7, 0.5, 2e-6, 9).finished();
  EXPECT_EQ(Carrying(z, 1, 4), (std::vector<int>{0, 2, 3}));
}

// a box at rest on the ground, with its resting guess's unknowns and every window face's
// multiplier `spread` besides the guess's active one
struct RestingBox {
  HullIsland island;
  IslandLayout layout;
  VectorXd z;
  McpOptions options;
  AdvanceResult result;
};

RestingBox RestingBoxWithSpread(double spread) {
  const Scene scene = BoxScene(0.025);
  RestingBox r{PrepareHullIsland(scene, InitialState(scene)), {}, {}, {}, {}};
  r.layout = MakeIslandLayout(r.island.problem);
  r.z = MakeGuess(Guess::kResting, scene.gravity, r.island.problem, r.layout, r.island.local,
                  r.island.scales);
  const MncpLayout::Contact& L = r.layout.contacts[0];
  for (int i = 0; i < L.l_count; ++i) r.z[L.l + i] = std::max(r.z[L.l + i], spread);
  r.options.tolerance = scene.solver.tolerance;
  r.options.jacobian_smoothing = kJacobianSmoothing;
  r.options.stall_iterations = kStallIterations;
  return r;
}

TEST(SolveOnCarryingFacesTest, WeaklyActiveFacesLeftOutTheStepIsSolved) {
  RestingBox r = RestingBoxWithSpread(1e-9);
  ASSERT_GT(r.layout.contacts[0].l_count, 1);
  EXPECT_TRUE(SolveOnCarryingFaces(r.island.problem, r.layout, r.z, r.options, r.island.scales, 0,
                                   r.island.workspace, r.island.local, r.result));
  EXPECT_NEAR(r.island.local.contacts[0].p_n, 2 * 9.8 * 0.01, kImpulseTolerance);
  EXPECT_GT(r.result.iterations, 0);
}

TEST(SolveOnCarryingFacesTest, NothingToCutNothingSolved) {
  RestingBox r = RestingBoxWithSpread(1);  // every face carries alike
  EXPECT_FALSE(SolveOnCarryingFaces(r.island.problem, r.layout, r.z, r.options, r.island.scales, 0,
                                    r.island.workspace, r.island.local, r.result));
  EXPECT_EQ(r.result.iterations, 0);
}

TEST(SolveAtDegenerateVertexTest, FacesLeftOutOneAtATimeUntilTheRootHolds) {
  RestingBox r = RestingBoxWithSpread(1);
  ASSERT_GE(r.layout.contacts[0].l_count, 4) << "four or more active faces";
  EXPECT_FALSE(SolveAtDegenerateVertex(r.island.problem, r.layout, r.z, r.options, r.island.scales,
                                       0, r.island.workspace, r.island.local, r.result, 0));
  EXPECT_TRUE(SolveAtDegenerateVertex(r.island.problem, r.layout, r.z, r.options, r.island.scales,
                                      0, r.island.workspace, r.island.local, r.result));
  EXPECT_NEAR(r.island.local.contacts[0].p_n, 2 * 9.8 * 0.01, kImpulseTolerance);
}

TEST(SolveAtDegenerateVertexTest, AnOctahedronOnItsTipIsSolvedWhereFourFacesMeet) {
  // a 1 kg octahedron of half-diagonal 5 cm at rest on its lowest vertex, where four faces meet:
  // their multipliers are not unique, and a start that spreads the contact over all four (as a
  // Newton iterate stalled between their planes does) is solved with one of them left out
  const double a = 0.05;
  geometry::TriangleMesh octahedron;
  octahedron.vertices = {{a, 0, 0}, {-a, 0, 0}, {0, a, 0}, {0, -a, 0}, {0, 0, a}, {0, 0, -a}};
  for (int top : {4, 5}) {
    const bool up = top == 4;
    const int ring[4] = {0, 2, 1, 3};  // counter-clockwise seen from +z
    for (int k = 0; k < 4; ++k) {
      const int u = ring[k], v = ring[(k + 1) % 4];
      octahedron.triangles.emplace_back(up ? Eigen::Vector3i(u, v, top)
                                           : Eigen::Vector3i(v, u, top));
    }
  }
  Body body = MakeMeshBody(octahedron, 1, "octahedron");
  body.p0 = Vector3d(0, 0, a);
  Scene scene = engine::testing::MakeGroundScene({body}, 0.01, Friction{0.5, 1, 1, 0.01});
  scene.model = ContactModel::kHull;
  HullIsland c = PrepareHullIsland(scene, InitialState(scene));
  const IslandLayout layout = MakeIslandLayout(c.problem);
  VectorXd z = MakeGuess(Guess::kResting, scene.gravity, c.problem, layout, c.local, c.scales);
  const MncpLayout::Contact& L = layout.contacts[0];
  const std::vector<int>& window = c.problem.contacts[0].window;
  const geometry::ConvexShape& hull = *c.problem.contacts[0].hull;
  // the faces through the tip share its multipliers equally
  constexpr double kOnFaceRel = 1e-12;  // of the size a: the tip lies on its faces to round-off
  int at_tip = 0;
  for (int i = 0; i < L.l_count; ++i) {
    const bool through_tip = std::abs(hull.Value(window[i], Vector3d(0, 0, -a))) < kOnFaceRel * a;
    z[L.l + i] = through_tip ? 0.25 : 0;
    at_tip += through_tip;
  }
  ASSERT_EQ(at_tip, 4);
  McpOptions options;
  options.tolerance = scene.solver.tolerance;
  options.jacobian_smoothing = kJacobianSmoothing;
  options.stall_iterations = kStallIterations;
  AdvanceResult result;
  EXPECT_TRUE(SolveAtDegenerateVertex(c.problem, layout, z, options, c.scales, 0, c.workspace,
                                      c.local, result));
  EXPECT_NEAR(c.local.contacts[0].p_n, 9.8 * 0.01, kImpulseTolerance);
  // the ECP at the tip, to the window check's tolerance of its size
  EXPECT_LE(c.local.contacts[0].a1.norm(), kWindowCheckRelTol * a);
}

TEST(SolveAlongCarryingEdgeTest, TwoCarryingFacesAreSolvedFromStartsAlongTheirEdge) {
  RestingBox r = RestingBoxWithSpread(0);
  const MncpLayout::Contact& L = r.layout.contacts[0];
  // the guess's active face (the bottom) and a side face carry: their edge
  const std::vector<int>& window = r.island.problem.contacts[0].window;
  const geometry::ConvexShape& hull = *r.island.problem.contacts[0].hull;
  int side = -1;
  for (int i = 0; i < L.l_count; ++i)
    if (std::abs(hull.Gradient(window[i], Vector3d::Zero()).normalized().z()) < 0.5) side = i;
  ASSERT_GE(side, 0);
  r.z[L.l + side] = 0.5;
  EXPECT_TRUE(SolveAlongCarryingEdge(r.island.problem, r.layout, r.z, r.options, r.island.scales, 0,
                                     r.island.workspace, r.island.local, r.result));
  EXPECT_NEAR(r.island.local.contacts[0].p_n, 2 * 9.8 * 0.01, kImpulseTolerance);
  // one carrying face has no edge to start along
  RestingBox one = RestingBoxWithSpread(0);
  EXPECT_FALSE(SolveAlongCarryingEdge(one.island.problem, one.layout, one.z, one.options,
                                      one.island.scales, 0, one.island.workspace, one.island.local,
                                      one.result));
}

TEST(StalledContactTest, TheContactWhoseRowsHoldTheLargestResidual) {
  // the stack's solved step, then one contact's ECP moved 1 cm up, off its root
  const Scene scene = StackScene();
  HullIsland c = PrepareHullIsland(scene, InitialState(scene));
  const IslandLayout layout = MakeIslandLayout(c.problem);
  VectorXd z = MakeGuess(Guess::kResting, scene.gravity, c.problem, layout, c.local, c.scales);
  McpOptions options;
  options.tolerance = scene.solver.tolerance;
  options.jacobian_smoothing = kJacobianSmoothing;
  AdvanceResult result;
  ASSERT_EQ(SolveAttempt(c.problem, layout, z, options, c.scales, 0, c.workspace, result).outcome,
            Outcome::kSolved);
  for (int k = 0; k < static_cast<int>(layout.contacts.size()); ++k) {
    VectorXd moved = z;
    moved[layout.contacts[k].a1 + 2] += 0.01;
    EXPECT_EQ(StalledContact(c.problem, layout, moved, c.scales), k);
  }
}

}  // namespace
}  // namespace ecpsim::engine::hull
