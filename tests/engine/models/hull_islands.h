#pragma once
// Small hand-made islands for the hull model's parts (hull_problem, hull_guesses, hull_attempt,
// hull_stall_recovery): boxes on the ground z ≤ 0 or on each other, and the island problem of
// their next step as the hull model builds it.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "engine/contact_model.h"
#include "engine/islands.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/models/hull_problem.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/state.h"
#include "engine/step_workspace.h"
#include "tests/engine/test_bodies.h"

// (in the hull model's namespace: the hull tests use them as their own)
namespace ecpsim::engine::hull {

/// A scene, its state, and its first island's problem of the next step with the hull model's
/// scales and windows (MakeHullProblem, MakeIslandScales, SeparatePairs, SelectWindows).
struct HullIsland {
  Scene scene;
  State state;
  Island island;
  IslandState local;
  IslandProblem problem;
  IslandScales scales;
  std::vector<double> overlaps;
  StepWorkspace workspace;  // what the island's solves work in
};

/// The island of the scene's body `body` at `state`, prepared as the hull model prepares it.
inline HullIsland PrepareHullIsland(Scene scene, State state, int body = 0) {
  HullIsland c{std::move(scene), std::move(state), {}, {}, {}, {}, {}, {}};
  for (const Island& island : FormIslands(c.scene, c.state)) {
    for (int b : island.bodies)
      if (b == body) c.island = island;
  }
  for (int b : c.island.bodies) c.local.bodies.push_back(c.state.bodies[b]);
  for (int k : c.island.contacts) c.local.contacts.push_back(c.state.contacts[k]);
  c.problem = MakeHullProblem(c.scene, c.island, c.state.t, c.scene.h, c.local);
  std::vector<FailedAttempt> tried;
  if (!MakeIslandScales(c.scene, c.island, c.problem, c.local, c.scales, tried)) {
    ADD_FAILURE() << "the free flight is not finite";
  }
  SeparatePairs(c.problem, c.scales, c.local, c.overlaps);
  SetStickCreep(c.scales, c.problem);
  SelectWindows(c.scene.solver, c.local, c.problem);
  return c;
}

/// A 0.2 × 0.1 × 0.05 m box of 2 kg (a polyhedral hull) on the ground (μ = 0.5) at height `z` of
/// its CM (0.025: on the ground), with velocity `v` and angular velocity `w`, turned by `q`. A
/// lower z starts it in the ground on purpose (the ejection tests), so that is allowed.
inline Scene BoxScene(double z, const Eigen::Vector3d& v = Eigen::Vector3d::Zero(),
                      const Eigen::Vector3d& w = Eigen::Vector3d::Zero(),
                      const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  Body box = engine::MakeBoxBody(Eigen::Vector3d(0.2, 0.1, 0.05), 2);
  box.p0 = Eigen::Vector3d(0, 0, z);
  box.allow_initial_penetration = z < 0.025;
  box.v0 = v;
  box.w0 = w;
  box.q0 = q;
  Scene scene = engine::testing::MakeGroundScene({box}, 0.01, Friction{0.5, 1, 1, 0.01});
  scene.model = ContactModel::kHull;
  return scene;
}

/// Two such boxes, the second resting on the first, each in contact with the ground and with
/// each other.
inline Scene StackScene() {
  Body lower = engine::MakeBoxBody(Eigen::Vector3d(0.2, 0.1, 0.05), 2, "lower");
  Body upper = engine::MakeBoxBody(Eigen::Vector3d(0.2, 0.1, 0.05), 2, "upper");
  lower.p0 = Eigen::Vector3d(0, 0, 0.025);
  upper.p0 = Eigen::Vector3d(0, 0, 0.075);
  Scene scene = engine::testing::MakeGroundScene({lower, upper}, 0.01, Friction{0.5, 1, 1, 0.01});
  AddBodyPairs(scene);
  scene.model = ContactModel::kHull;
  return scene;
}

}  // namespace ecpsim::engine::hull
