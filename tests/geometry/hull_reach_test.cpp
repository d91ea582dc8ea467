// ReachesWithin: how far a convex hull reaches out of a solid, against closed forms for a cube;
// and SolidDistance, the distances it takes.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/convex_hull.h"
#include "geometry/hull_reach.h"
#include "test_meshes.h"

namespace ecpsim::geometry {
namespace {

using testing::MakeBoxMesh;

TEST(SolidDistanceTest, AUnitCubesDistancesAndInside) {
  const SolidDistance cube(MakeBoxMesh({0, 0, 0}, {1, 1, 1}), "cube");
  EXPECT_NEAR(cube.ToSurface({0.5, 0.5, 0.5}), 0.5, 1e-15);
  EXPECT_NEAR(cube.ToSurface({0.5, 0.5, 1.25}), 0.25, 1e-15);
  EXPECT_NEAR(cube.ToSurface({2, 2, 0.5}), std::sqrt(2.0), 1e-15);
  EXPECT_TRUE(cube.Inside({0.5, 0.2, 0.9}));
  EXPECT_FALSE(cube.Inside({0.5, 0.2, 1.1}));
}

TEST(ReachesWithinTest, AHullReachingAboveACubeIsWithinOnlyTwiceItsReach) {
  // the cube [0, 1]³ and the box [0, 1]² × [0, 1 + e] over it: its top reaches e out, at every
  // point of its top face
  const TriangleMesh mesh = MakeBoxMesh({0, 0, 0}, {1, 1, 1});
  const SolidDistance cube(mesh, "cube");
  const double e = 0.01;
  const ConvexHull taller = ComputeConvexHull(MakeBoxMesh({0, 0, 0}, {1, 1, 1 + e}).vertices);
  EXPECT_TRUE(ReachesWithin(taller, {}, mesh, cube, 2 * e));
  EXPECT_FALSE(ReachesWithin(taller, {}, mesh, cube, 0.9 * e));
  // a hull inside the cube is within any bound, at once (the surface does not enter it)
  const ConvexHull inner = ComputeConvexHull(MakeBoxMesh({0.2, 0.2, 0.2}, {0.8, 0.8, 1}).vertices);
  EXPECT_TRUE(ReachesWithin(inner, {}, mesh, cube, 1e-9));
}

TEST(ReachesWithinTest, AKnownPartIsNotCheckedAgain) {
  // the taller box as a part known to be within the bound: a hull made of it and a box inside
  // the cube is accepted at a bound the taller box alone would fail
  const TriangleMesh mesh = MakeBoxMesh({0, 0, 0}, {1, 1, 1});
  const SolidDistance cube(mesh, "cube");
  const ConvexHull taller = ComputeConvexHull(MakeBoxMesh({0, 0, 0}, {1, 1, 1.01}).vertices);
  EXPECT_FALSE(ReachesWithin(taller, {}, mesh, cube, 0.005));
  EXPECT_TRUE(ReachesWithin(taller, {&taller}, mesh, cube, 0.005));
}

}  // namespace
}  // namespace ecpsim::geometry
