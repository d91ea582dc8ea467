#include "engine/report/penetration.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "engine/scene_io/scene_builders.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"
#include "geometry/paper_bodies.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using testing::MakeBoxBody;
using testing::MakeGroundScene;

// depths are differences of O(1) coordinates: a few ulps
constexpr double kTight = 1e-14;

// `body` resting on the ground at t = 0 (its lowest mesh vertex at z = 0): a scene the builders
// accept; the probe is then asked at the poses of each test
Body OnTheGround(Body body) {
  double lowest = 0;
  for (const Eigen::Vector3d& v : body.mesh.vertices) lowest = std::min(lowest, v.z());
  body.p0 = Eigen::Vector3d(0, 0, -lowest);
  return body;
}

State Posed(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  State state;
  BodyState b;
  b.p_WB = p;
  b.Q_WB = q;
  state.bodies.push_back(b);
  return state;
}

TEST(PenetrationTest, FlatBoxSunkIntoTheGround) {
  const Scene scene = MakeGroundScene({OnTheGround(MakeBoxBody({1, 1, 1}, 1))});
  const PenetrationProbe probe(scene);
  // a box's mesh is its hull: all 8 corners are the half-space candidates
  ASSERT_EQ(probe.half_space_vertices().size(), 1u);
  EXPECT_EQ(probe.half_space_vertices()[0].size(), 8u);
  EXPECT_NEAR(probe.MaxDepth(scene, Posed({0, 0, 0.49}, Eigen::Quaterniond::Identity())), 0.01,
              kTight);
  EXPECT_EQ(probe.MaxDepth(scene, Posed({0, 0, 0.5}, Eigen::Quaterniond::Identity())), 0);
  EXPECT_EQ(probe.MaxDepth(scene, Posed({0, 0, 2}, Eigen::Quaterniond::Identity())), 0);
}

TEST(PenetrationTest, BoxOnAnEdgeReachesDownHalfItsDiagonal) {
  // a unit cube turned 45° about x reaches √2/2 below its centre
  const Scene scene = MakeGroundScene({OnTheGround(MakeBoxBody({1, 1, 1}, 1))});
  const PenetrationProbe probe(scene);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(probe.MaxDepth(scene, Posed({0, 0, 0.6}, q)), std::sqrt(0.5) - 0.6, kTight);
}

TEST(PenetrationTest, BoxFixtureDepthIsTheDistanceToItsNearestFace) {
  // a 0.2 m cube centred at (0.55, 0, 0) pokes 0.05 m into the unit fixture's x = 0.5 face
  Scene scene = MakeGroundScene({OnTheGround(MakeBoxBody({0.2, 0.2, 0.2}, 1))});
  scene.obstacles[0].shape = geometry::MakeBox(Eigen::Vector3d(0.5, 0.5, 0.5));
  const PenetrationProbe probe(scene);
  EXPECT_NEAR(probe.MaxDepth(scene, Posed({0.55, 0, 0}, Eigen::Quaterniond::Identity())), 0.05,
              kTight);
  EXPECT_EQ(probe.MaxDepth(scene, Posed({0.61, 0, 0}, Eigen::Quaterniond::Identity())), 0);
}

TEST(PenetrationTest, HullVerticesGiveTheExactDepthOfANonConvexMesh) {
  // the T-bar's hull has far fewer vertices than its mesh; for the ground plane checking them is
  // exact, so it matches the brute force over every mesh vertex at any pose
  const geometry::TriangleMesh mesh = geometry::MakeTBarMesh();
  const geometry::MassProperties mp = geometry::ComputeMassPropertiesForMass(mesh, 2);
  Body body;
  body.name = "tbar";
  body.mesh = mesh;
  for (Eigen::Vector3d& v : body.mesh.vertices) v -= mp.center_of_mass;
  body.hull = std::make_shared<geometry::PolyhedralShape>(
      geometry::TranslateHull(geometry::ComputeConvexHull(mesh.vertices), -mp.center_of_mass));
  const Scene scene = MakeGroundScene({OnTheGround(body)});
  const PenetrationProbe probe(scene);
  const auto& candidates = probe.half_space_vertices()[0];
  const auto* hull = body.hull->AsPolyhedron();
  EXPECT_EQ(candidates.size(), hull->hull().vertices.size());
  EXPECT_LT(candidates.size(), body.mesh.vertices.size());

  for (int k = 0; k < 20; ++k) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d(1, 2, 3).normalized()));
    const Eigen::Vector3d p(0, 0, 0.1 - 0.01 * k);
    double brute = 0;
    for (const Eigen::Vector3d& v : body.mesh.vertices) brute = std::max(brute, -(p + q * v).z());
    EXPECT_NEAR(probe.MaxDepth(scene, Posed(p, q)), brute, kTight) << "k = " << k;
  }
}

TEST(PenetrationTest, PrimitiveHullChecksEveryMeshVertex) {
  // a sphere hull is not polyhedral: every vertex of the display mesh is a candidate
  Body ball;
  ball.name = "ball";
  ball.hull = geometry::MakeSphere(0.5);
  ball.mesh = ball.hull->Tessellate(16);
  const Scene scene = MakeGroundScene({OnTheGround(ball)});
  const PenetrationProbe probe(scene);
  EXPECT_EQ(probe.half_space_vertices()[0].size(), ball.mesh.vertices.size());
  double lowest = 0;
  for (const Eigen::Vector3d& v : ball.mesh.vertices) lowest = std::min(lowest, v.z());
  EXPECT_NEAR(probe.MaxDepth(scene, Posed({0, 0, 0.4}, Eigen::Quaterniond::Identity())),
              -lowest - 0.4, kTight);
}

TEST(PenetrationTest, StackedBoxesSunkIntoEachOtherBothWaysAndExcludedPairsIgnored) {
  // a 0.2 m cube on a 0.4 m one, both resting on the ground; the top one 1 mm too low, then a
  // corner of a turned small cube pressed into the big one's side
  Body big = OnTheGround(MakeBoxBody({0.4, 0.4, 0.4}, 1, "big"));
  Body small = OnTheGround(MakeBoxBody({0.2, 0.2, 0.2}, 1, "small"));
  small.p0.x() = 1;
  Scene scene = MakeGroundScene({big, small});
  AddBodyPairs(scene);
  const PenetrationProbe probe(scene);
  State state = Posed({0, 0, 0.2}, Eigen::Quaterniond::Identity());
  state.bodies.push_back(state.bodies[0]);
  state.bodies[1].p_WB = {0.05, 0, 0.499};
  EXPECT_NEAR(probe.BodyDepth(scene, state, 0, 1), 0.001, kTight);
  EXPECT_NEAR(probe.BodyDepth(scene, state, 1, 0), 0.001, kTight);
  EXPECT_NEAR(probe.MaxDepth(scene, state), 0.001, kTight);
  state.bodies[1].p_WB.z() = 0.5;
  EXPECT_NEAR(probe.BodyDepth(scene, state, 0, 1), 0, kTight);
  // turned 45° about z, its edge-on corner 2 mm into the big cube's +x face
  state.bodies[1].Q_WB = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ());
  state.bodies[1].p_WB = {0.2 + 0.1 * std::sqrt(2.0) - 0.002, 0, 0.2};
  EXPECT_NEAR(probe.BodyDepth(scene, state, 0, 1), 0.002, kTight);
  // an excluded pair (not in the contacts) is not measured
  scene.contacts.pop_back();
  EXPECT_EQ(probe.MaxDepth(scene, state), 0);
}

}  // namespace
}  // namespace ecpsim::engine
