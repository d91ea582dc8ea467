// The clutter benchmark's bin: the same boxes for a seed, boxes of the stated sizes and mass that
// start inside the bin without touching, every pair that can touch, and a first landing the hull
// model solves without penetration.

#include "evaluation/clutter_bin.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "engine/report/penetration.h"
#include "engine/state.h"
#include "engine/time_step.h"
#include "tests/tolerances.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::Vector3d;

constexpr std::uint64_t kSeed = 7;
constexpr double kStep = 0.01;  // s, the bench's coarse step
// the obstacles: the floor and four walls
constexpr int kObstacles = 5;
// m: a rigid solution does not penetrate; the engine's depth is its tolerance on the gap, 1e-9
// of the bodies' size at most (engine/README.md), and a 4 cm box's is 4e-11 m
constexpr double kMaxPenetration = 1e-9 * kClutterEdgeMin;
// s: the first layer lands at about 0.14 s (a fall of one pitch less half a box); by 0.2 s its
// boxes have hit the floor and each other
constexpr double kFirstLanding = 0.2;

// a box's edge along its own axis `axis`, from its hull
double Edge(const engine::Body& box, int axis) {
  const Vector3d u = Vector3d::Unit(axis);
  return u.dot(box.hull->Support(u)) - u.dot(box.hull->Support(-u));
}

TEST(ClutterBin, TheSameSeedDropsTheSameBoxesTheSameWay) {
  const engine::Scene a = ClutterBinScene(24, kSeed, kStep), b = ClutterBinScene(24, kSeed, kStep);
  const engine::Scene other = ClutterBinScene(24, kSeed + 1, kStep);
  bool differs = false;
  for (size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].mass, b.bodies[i].mass);
    EXPECT_EQ(a.bodies[i].p0, b.bodies[i].p0);
    EXPECT_EQ(a.bodies[i].q0.coeffs(), b.bodies[i].q0.coeffs());
    differs =
        differs || a.bodies[i].p0 != other.bodies[i].p0 || a.bodies[i].mass != other.bodies[i].mass;
  }
  EXPECT_TRUE(differs) << "seeds " << kSeed << " and " << kSeed + 1 << " gave the same bin";
  // indexed with its walls' and its boxes' pairs (engine/contact_index.h)
  ASSERT_NE(a.contact_index, nullptr);
  EXPECT_TRUE(a.contact_index->Fits(a));
}

TEST(ClutterBin, BoxesOfTheStatedSizesStartInsideTheBinApart) {
  for (int n : {1, 24, 96}) {
    const engine::Scene scene = ClutterBinScene(n, kSeed, kStep);
    ASSERT_EQ(static_cast<int>(scene.bodies.size()), n);
    ASSERT_EQ(static_cast<int>(scene.obstacles.size()), kObstacles);
    EXPECT_DOUBLE_EQ(scene.duration, 2 * kClutterSettleTime);
    const double half = 0.5 * kClutterBinSide;
    for (int i = 0; i < n; ++i) {
      const engine::Body& box = scene.bodies[i];
      const Vector3d edges(Edge(box, 0), Edge(box, 1), Edge(box, 2));
      EXPECT_GE(edges.minCoeff(), kClutterEdgeMin - kUnitRoundOff) << box.name;
      EXPECT_LT(edges.maxCoeff(), kClutterEdgeMax + kUnitRoundOff) << box.name;
      EXPECT_NEAR(box.mass, kClutterDensity * edges.prod(), 1e-12 * box.mass) << box.name;
      // every corner inside the walls and above the floor
      for (const Vector3d& d : {Vector3d(1, 0, 0), Vector3d(-1, 0, 0), Vector3d(0, 1, 0),
                                Vector3d(0, -1, 0), Vector3d(0, 0, -1)}) {
        const Vector3d deepest = box.p0 + box.q0 * box.hull->Support(box.q0.inverse() * d);
        EXPECT_LT(d.dot(deepest), d.z() < 0 ? 0 : half) << box.name << " along " << d.transpose();
      }
      // apart: the spheres about their boxes do not meet
      for (int j = 0; j < i; ++j) {
        const engine::Body& other = scene.bodies[j];
        const double reach =
            0.5 * (edges.norm() + Vector3d(Edge(other, 0), Edge(other, 1), Edge(other, 2)).norm());
        EXPECT_GT((box.p0 - other.p0).norm(), reach) << box.name << " and " << other.name;
      }
    }
    // every box against the floor and each wall, and every two boxes
    EXPECT_EQ(static_cast<int>(scene.contacts.size()), n * kObstacles + n * (n - 1) / 2);
  }
}

TEST(ClutterBin, TheHullModelLandsTheFirstLayerWithoutPenetration) {
  engine::Scene scene = ClutterBinScene(24, kSeed, kStep);
  scene.model = engine::ContactModel::kHull;
  const engine::PenetrationProbe probe(scene);
  engine::State state = engine::InitialState(scene);
  double deepest = 0;
  while (state.t < kFirstLanding - 0.5 * kStep) {
    ASSERT_TRUE(engine::Step(scene, state).converged) << "t = " << state.t;
    deepest = std::max(deepest, probe.MaxDepth(scene, state));
  }
  EXPECT_LE(deepest, kMaxPenetration);
  // the first layer is down: its lowest box rests on the floor
  double lowest = INFINITY;
  for (const engine::BodyState& b : state.bodies) lowest = std::min(lowest, b.p_WB.z());
  EXPECT_LT(lowest, kClutterEdgeMax);
}

}  // namespace
}  // namespace ecpsim::evaluation
