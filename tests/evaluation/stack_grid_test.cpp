// The scaling benchmark's grid of stacks: its body count, stacks and pairs, boxes that touch
// without overlapping, and a grid that stays at rest under the hull model.

#include "evaluation/stack_grid.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <gtest/gtest.h>

#include "engine/scene_io/scene_validation.h"
#include "engine/state.h"
#include "engine/time_step.h"
#include "tests/tolerances.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

// the counts around a stack's size, a grid whose last row is short, and the benchmark's largest
const int kSizes[] = {1, 3, 4, 5, 8, 17, 64, 1000};

AlignedBox3d WorldBox(const engine::Body& body) {
  const Vector3d half = Vector3d::Constant(kGridBoxSize / 2);
  return AlignedBox3d(body.p0 - half, body.p0 + half);
}

// the stack a body belongs to: its column on the grid, (x, y) to round-off
std::pair<long, long> Column(const engine::Body& body) {
  return {std::lround(body.p0.x() / kStackSpacing * 2),
          std::lround(body.p0.y() / kStackSpacing * 2)};
}

TEST(StackGrid, HasTheBodiesInStacksOfFour) {
  for (int n : kSizes) {
    const engine::Scene scene = MakeStackGrid(n);
    ASSERT_EQ(scene.bodies.size(), static_cast<size_t>(n));
    std::map<std::pair<long, long>, int> heights;
    for (const engine::Body& b : scene.bodies) {
      ++heights[Column(b)];
      EXPECT_EQ(b.mass, kGridBoxMass);
      EXPECT_TRUE(b.q0.isApprox(Eigen::Quaterniond::Identity()));
      EXPECT_EQ(b.v0, Vector3d::Zero());
      EXPECT_EQ(b.w0, Vector3d::Zero());
    }
    EXPECT_EQ(heights.size(), static_cast<size_t>((n + kStackHeight - 1) / kStackHeight)) << n;
    for (const auto& [column, height] : heights) EXPECT_LE(height, kStackHeight);
    EXPECT_NO_THROW(engine::ValidateScene(scene)) << n;
  }
}

TEST(StackGrid, BoxesTouchWithoutOverlapAndRestOnTheGroundOrABox) {
  for (int n : kSizes) {
    const engine::Scene scene = MakeStackGrid(n);
    const auto& bodies = scene.bodies;
    for (size_t i = 0; i < bodies.size(); ++i) {
      const AlignedBox3d a = WorldBox(bodies[i]);
      // its support: the ground, or the top of a box of its stack exactly below it
      bool supported = std::abs(a.min().z()) <= kUnitRoundOff;
      for (size_t j = 0; j < bodies.size(); ++j) {
        if (j == i) continue;
        const AlignedBox3d b = WorldBox(bodies[j]);
        // touching boxes share a face at most: their intersection has no volume
        const AlignedBox3d common = a.intersection(b);
        if (!common.isEmpty()) {
          EXPECT_LE(common.volume(), kUnitRoundOff) << bodies[i].name << " " << bodies[j].name;
        }
        supported |= Column(bodies[i]) == Column(bodies[j]) &&
                     std::abs(a.min().z() - b.max().z()) <= kUnitRoundOff;
      }
      EXPECT_TRUE(supported) << bodies[i].name << " of " << n;
    }
  }
}

TEST(StackGrid, PairsAreTheGroundAndTheBoxesOfOneStack) {
  for (int n : kSizes) {
    const engine::Scene scene = MakeStackGrid(n);
    int ground = 0, between = 0, expected_between = 0;
    for (const engine::ContactPair& pair : scene.contacts) {
      if (!pair.WithBody()) {
        ++ground;
        continue;
      }
      ++between;
      EXPECT_EQ(Column(scene.bodies[pair.body]), Column(scene.bodies[pair.other_body]));
    }
    // h boxes in a stack make h (h − 1) / 2 pairs
    for (int left = n; left > 0; left -= kStackHeight) {
      const int h = std::min(left, kStackHeight);
      expected_between += h * (h - 1) / 2;
    }
    EXPECT_EQ(ground, n);
    EXPECT_EQ(between, expected_between) << n;
    // indexed with its pairs (engine/contact_index.h), so that a step need not index it
    ASSERT_NE(scene.contact_index, nullptr);
    EXPECT_TRUE(scene.contact_index->Fits(scene)) << n;
  }
}

TEST(StackGrid, StaysAtRestUnderTheHullModel) {
  // two stacks of four: the hull model holds a stack to round-off (scenes/stack.yaml drifts
  // under 1e-9 m in 10 s, tests/engine/body_contact_test.cpp)
  constexpr double kRestDrift = 1e-9;  // m, over the steps below
  constexpr int kSteps = 20;
  engine::Scene scene = MakeStackGrid(8);
  scene.model = engine::ContactModel::kHull;
  engine::State state = engine::InitialState(scene);
  engine::StepWorkspace workspace;
  for (int k = 0; k < kSteps; ++k) engine::Step(scene, state, workspace);
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    EXPECT_LE((state.bodies[i].p_WB - scene.bodies[i].p0).norm(), kRestDrift)
        << scene.bodies[i].name;
  }
}

}  // namespace
}  // namespace ecpsim::evaluation
