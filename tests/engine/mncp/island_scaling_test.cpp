#include "engine/mncp/island_scaling.h"

#include <gtest/gtest.h>

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using Other = IslandContact::Other;

// Two bodies (a large slow heavy one and a small fast light one), a kinematic belt, and one
// contact of each kind
struct TwoBodies {
  std::shared_ptr<const geometry::ConvexShape> box = geometry::MakeBox(Vector3d(0.2, 0.1, 0.1));
  std::shared_ptr<const geometry::ConvexShape> ground =
      geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  IslandProblem problem;
  IslandScales scales;

  TwoBodies() {
    problem.h = 0.01;
    for (double x : {-3.0, 40.0}) {
      BodyProblem body;
      body.h = problem.h;
      body.c = Vector3d(x, 1, 0.5);
      body.inertia_world.setIdentity();
      body.p_ext.setZero();
      problem.bodies.push_back(body);
    }
    problem.kinematic.push_back(
        {Vector3d(0, -70, 0), Eigen::Matrix3d::Identity(), Vector3d(1, 0, 0), Vector3d::Zero()});
    scales.bodies = {{2.0, 0.1, 50.0}, {0.1, 3.0, 0.3}};  // {length m, velocity m/s, impulse N·s}
    const auto add = [&](int body, Other kind, int other) {
      IslandContact cp;
      cp.body = body;
      cp.other_kind = kind;
      cp.other = other;
      cp.hull = cp.other_shape = box.get();
      if (kind == Other::kFixed) cp.other_shape = ground.get();
      cp.window = {0, 1};
      cp.other_window = {0};
      problem.contacts.push_back(cp);
    };
    add(0, Other::kFixed, -1);
    add(1, Other::kKinematic, 0);
    add(0, Other::kBody, 1);
  }
};

TEST(IslandScalingTest, ContactScalesAreTheBodysOwnOrTheTighterOfTwo) {
  const TwoBodies t;
  const Scales fixed = ContactScales(t.problem, t.scales, 0);
  EXPECT_EQ(fixed.length, 2.0);
  EXPECT_EQ(fixed.velocity, 0.1);
  EXPECT_EQ(fixed.impulse, 50.0);
  const Scales kinematic = ContactScales(t.problem, t.scales, 1);
  EXPECT_EQ(kinematic.length, 0.1);
  EXPECT_EQ(kinematic.velocity, 3.0);
  EXPECT_EQ(kinematic.impulse, 0.3);
  // between the bodies each scale is the smaller one, whichever body it comes from
  const Scales pair = ContactScales(t.problem, t.scales, 2);
  EXPECT_EQ(pair.length, 0.1);
  EXPECT_EQ(pair.velocity, 0.1);
  EXPECT_EQ(pair.impulse, 0.3);
}

TEST(IslandScalingTest, RowsAndUnknownsInTheirBodysAndContactsUnits) {
  const TwoBodies t;
  const IslandLayout layout = MakeIslandLayout(t.problem);
  const Eigen::VectorXd var = IslandVariableScales(t.problem, layout, t.scales);
  const Eigen::VectorXd row = IslandRowScales(t.problem, layout, t.scales);
  // each body's ν⁺ in its own V and V / L; its Newton–Euler rows in 1/P and 1/(P L)
  for (int b = 0; b < 2; ++b) {
    const Scales& s = t.scales.bodies[b];
    const int col = IslandLayout::Velocity(b);
    EXPECT_EQ(var[col], s.velocity);
    EXPECT_EQ(var[col + 3], s.velocity / s.length);
    EXPECT_EQ(row[col], 1 / s.impulse);
    EXPECT_EQ(row[col + 3], 1 / (s.impulse * s.length));
  }
  // the body–body contact's lengths in 0.1 m and impulses in 0.3 N·s
  const MncpLayout::Contact& L = layout.contacts[2];
  EXPECT_EQ(var[L.a1], 0.1);
  EXPECT_EQ(var[L.p_n], 0.3);
  EXPECT_EQ(var[L.sigma], 0.1);
  EXPECT_EQ(row[L.a1], 1 / 0.1);
  EXPECT_EQ(row[L.l_g], 1 / 0.1);
  EXPECT_EQ(row[L.p_t], 1 / (0.3 * 0.1));
}

TEST(IslandScalingTest, ResidualUnitsAndEnergyScale) {
  TwoBodies t;
  const IslandResidualUnits units = MakeIslandResidualUnits(t.problem, t.scales, 1e-10);
  EXPECT_EQ(units.tolerance, 1e-10);
  EXPECT_EQ(units.body_length, std::vector<double>({2.0, 0.1}));
  EXPECT_EQ(units.contact_length, std::vector<double>({2.0, 0.1, 0.1}));
  // the largest |coordinate| of the centres the contact joins: body 0 alone, body 1 and the
  // belt's origin, both bodies
  EXPECT_EQ(units.contact_coordinates, std::vector<double>({3.0, 70.0, 40.0}));

  t.problem.bodies[0].mass = 4;
  t.problem.bodies[1].mass = 0.5;
  for (BodyProblem& body : t.problem.bodies) body.p_ext << 0, 0, -9.8 * body.mass * body.h, 0, 0, 0;
  EXPECT_DOUBLE_EQ(IslandEnergyScale(t.problem, t.scales),
                   EnergyScale(t.problem.bodies[0], t.scales.bodies[0]) +
                       EnergyScale(t.problem.bodies[1], t.scales.bodies[1]));
}

}  // namespace
}  // namespace ecpsim::engine
