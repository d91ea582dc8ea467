// The hull model's island problem, piece by piece, on small hand-made islands: what it holds,
// the windows' multipliers carried by face, the scales raised in coupled islands, the pairs'
// separating normals and the energy an ejection may give.

#include "engine/models/hull_problem.h"

#include <cmath>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "engine/mncp/island_mncp.h"
#include "engine/models/hull_model.h"
#include "engine/models/hull_warm_start.h"
#include "tests/engine/models/hull_islands.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

// m, m/s, J: round-off of the few operations between the closed forms and the code
constexpr double kRoundOff = 1e-15;

TEST(MakeHullProblemTest, ABoxOnTheGroundIsOneBodyAgainstEveryGroundConstraint) {
  const HullIsland c = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  ASSERT_EQ(c.problem.bodies.size(), 1u);
  ASSERT_EQ(c.problem.contacts.size(), 1u);
  const IslandContact& cp = c.problem.contacts[0];
  EXPECT_EQ(cp.other_kind, IslandContact::Other::kFixed);
  std::vector<int> every(cp.other_shape->NumConstraints());
  std::iota(every.begin(), every.end(), 0);
  EXPECT_EQ(cp.other_window, every);
  EXPECT_EQ(c.problem.h, c.scene.h);
  EXPECT_EQ(c.problem.bodies[0].mass, 2);
  // the window around the support in −z holds the bottom face, whose normal is −z
  const bool has_bottom = std::any_of(cp.window.begin(), cp.window.end(), [&](int i) {
    return cp.hull->Gradient(i, Vector3d(0, 0, -0.025)).normalized().z() < -1 + kRoundOff;
  });
  EXPECT_TRUE(has_bottom);
}

TEST(CarryByFaceTest, MultipliersFollowTheirFaceAndNewFacesKeepTheirValue) {
  const VectorXd from = (VectorXd(4) << 9, 0.1, 0.5, 0.7).finished();  // faces 2, 5, 7 from 1
  VectorXd to = VectorXd::Constant(5, -1);
  CarryByFace({2, 5, 7}, from, 1, {5, 6, 7}, to, 2);
  EXPECT_EQ(to, (VectorXd(5) << -1, -1, 0.5, -1, 0.7).finished());
}

TEST(RemapWindowsTest, AWindowCutAndRestoredKeepsEveryUnknownButTheDroppedFace) {
  const HullIsland c = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  const IslandLayout layout = MakeIslandLayout(c.problem);
  VectorXd z(layout.size);
  std::iota(z.data(), z.data() + z.size(), 1.0);
  IslandProblem reduced = c.problem;
  std::vector<int>& window = reduced.contacts[0].window;
  ASSERT_GE(window.size(), 2u);
  const int dropped = window.front();
  window.erase(window.begin());
  const IslandLayout reduced_layout = MakeIslandLayout(reduced);
  const VectorXd rz = RemapWindows(c.problem, layout, z, reduced, reduced_layout);
  const VectorXd back = RemapWindows(reduced, reduced_layout, rz, c.problem, layout);
  const MncpLayout::Contact& L = layout.contacts[0];
  for (int i = 0; i < layout.size; ++i) {
    if (i == L.l) {
      EXPECT_EQ(back[i], 0) << "face " << dropped << " was left out";
    } else {
      EXPECT_EQ(back[i], z[i]) << "unknown " << i;
    }
  }
}

TEST(FlatOnOneFaceTest, OneCarryingFaceUnderANormalImpulse) {
  ContactState c;
  c.p_n = 0.2;
  HullWarmStart& warm = c.warm_start.Emplace<HullWarmStart>();
  warm.l = (VectorXd(3) << 0, 1, 1e-12).finished();  // 1e-12 ≤ kDegenerateActiveFraction
  EXPECT_TRUE(FlatOnOneFace(c));
  warm.l = (VectorXd(3) << 0, 0.5, 0.5).finished();  // an edge
  EXPECT_FALSE(FlatOnOneFace(c));
  warm.l = (VectorXd(3) << 0, 1, 0).finished();
  c.p_n = 0;  // touching without pressing
  EXPECT_FALSE(FlatOnOneFace(c));
  c.p_n = 0.2;
  c.warm_start.Reset();  // another model's contact
  EXPECT_FALSE(FlatOnOneFace(c));
}

TEST(CoupledTest, BodiesTouchingBodiesAreCoupled) {
  EXPECT_FALSE(Coupled(PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025))).problem));
  const HullIsland stack = PrepareHullIsland(StackScene(), InitialState(StackScene()));
  ASSERT_EQ(stack.problem.bodies.size(), 2u);
  EXPECT_TRUE(Coupled(stack.problem));
}

TEST(MakeIslandScalesTest, ACoupledIslandTakesItsFastestBodysVelocityScale) {
  Scene scene = StackScene();
  scene.bodies[1].v0 = Vector3d(1, 0, 0);
  const HullIsland c = PrepareHullIsland(scene, InitialState(scene));
  ASSERT_EQ(c.scales.bodies.size(), 2u);
  // the upper box's scale is its speed (1 m/s, more than g h); the lower one's is raised to it
  EXPECT_GE(c.scales.bodies[1].velocity, 1);
  EXPECT_EQ(c.scales.bodies[0].velocity, c.scales.bodies[1].velocity);
  EXPECT_EQ(c.scales.bodies[0].impulse, 2 * c.scales.bodies[0].velocity);
  // and its contacts creep at most kStickCreepFraction of it when they stick
  for (const IslandContact& cp : c.problem.contacts)
    EXPECT_EQ(cp.stick_creep, kStickCreepFraction * c.scales.bodies[cp.body].velocity);
  // a body alone keeps its own: g h at rest under gravity
  const HullIsland alone = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  EXPECT_NEAR(alone.scales.bodies[0].velocity, 9.8 * 0.01, kRoundOff);
  EXPECT_EQ(alone.problem.contacts[0].stick_creep, 0);
}

TEST(SeparatePairsTest, APairApartTakesItsSeparatingAxis) {
  // two boxes side by side on the ground, 1 mm apart along x, their pair's normal along z
  Scene scene = StackScene();
  scene.bodies[1].p0 = Vector3d(0.201, 0, 0.025);
  HullIsland c = PrepareHullIsland(scene, InitialState(scene));
  ASSERT_EQ(c.island.contacts.size(), 3u) << "the boxes are within each other's reach";
  c.local.contacts[2].n = Vector3d::UnitZ();
  SeparatePairs(c.problem, c.scales, c.local, c.overlaps);
  EXPECT_NEAR(std::abs(c.local.contacts[2].n.x()), 1, kRoundOff);
  EXPECT_NEAR(c.overlaps[2], -0.001, kRoundOff);
  EXPECT_EQ(c.overlaps[0], 0);  // the ground's contacts: fixed G
}

TEST(EjectionEnergyTest, ABodyStartingInTheGroundMayGainItsEjection) {
  // 1 mm deep at the start: out within the step h at d / h, J = m (d/h)² + |p_ext| d / h
  const Scene scene = BoxScene(0.024);
  const HullIsland c = PrepareHullIsland(scene, InitialState(scene));
  const double speed = (0.025 - 0.024) / scene.h;
  const double expected = 2 * speed * speed + 2 * 9.8 * scene.h * speed;
  EXPECT_NEAR(EjectionEnergy(c.problem, c.local, c.scales, c.overlaps), expected, kRoundOff);
  const HullIsland resting = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  EXPECT_EQ(EjectionEnergy(resting.problem, resting.local, resting.scales, resting.overlaps), 0);
}

}  // namespace
}  // namespace ecpsim::engine::hull
