// Grippers (engine/mncp/island_gripper.h, issue 13): the jaws' closing motion against its closed
// form, the jaws following the frame across the axis and in orientation, and a box held on the
// table: dragged at the frame's speed with the table's friction μ m g carried by the pads, left
// behind when the grip is too weak for that, and lifted off the table.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/islands.h"
#include "engine/models/hull_model.h"
#include "engine/report/trajectory_columns.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/step_driver.h"
#include "engine/step_report.h"
#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using testing::MakeBoxBody;

constexpr double kG = 9.8;
// relative: the solver's convergence bar on each row in the body's own scales (SolverSettings)
constexpr double kSolverTolerance = 1e-12;
// a creeping contact's slip holds to this many of the solver's bars τ V: its velocity rows sum
// several, and a margin (as the other engine tests' "10 τ V")
constexpr double kCreepSlipBars = 10;

// the jaws: pads 1 cm thick, 4 cm wide, 3 cm tall, of different masses (the coupling must not
// assume equal ones)
constexpr double kJaw0Mass = 0.05, kJaw1Mass = 0.08;  // kg
const Vector3d kPadSize(0.01, 0.04, 0.03);            // m

Body Jaw(const std::string& name, double mass, const Vector3d& position) {
  Body jaw = MakeBoxBody(kPadSize, mass, name);
  jaw.p0 = position;
  return jaw;
}

// a gripper whose frame moves by `motion`, its jaws bodies 0 and 1 of `scene`, closing along x
void AddHand(Scene& scene, KinematicMotion motion, TimeFunction force, int jaw0 = 0, int jaw1 = 1) {
  Gripper gripper;
  gripper.name = "hand";
  gripper.jaws = {jaw0, jaw1};
  gripper.motion = std::make_shared<const KinematicMotion>(std::move(motion));
  gripper.axis = Vector3d::UnitX();
  gripper.force = std::move(force);
  AddGripper(scene, std::move(gripper));
}

KinematicMotion StillFrame(const Vector3d& at) {
  ConstantTwist twist;
  twist.start.p = at;
  return KinematicMotion(twist, "test frame");
}

// no ground: jaws 0.5 m up, `half_opening` to either side of the frame's origin at t = 0 (in
// the frame, gravity acts across the axis)
Scene HangingJaws(double half_opening, KinematicMotion frame, double force) {
  Scene scene;
  scene.source = "test";
  scene.h = 0.01;
  scene.duration = 1;
  scene.bodies = {Jaw("jaw0", kJaw0Mass, Vector3d(-half_opening, 0, 0.5)),
                  Jaw("jaw1", kJaw1Mass, Vector3d(half_opening, 0, 0.5))};
  AddBodyPairs(scene);
  AddHand(scene, std::move(frame), TimeFunction(force));
  ValidateScene(scene);
  return scene;
}

TEST(GripperTest, FreeJawsCloseAsTheCoupledClosedFormSaysAndThenPressWithTheForce) {
  // no ground: the jaws hang in the frame (gravity across the axis) and close on nothing until
  // they meet. Coupled about the frame's centre, each closes at a = 2 F / (m_0 + m_1); the
  // implicit step gives the closing speed k h a after k steps and the gap closed 2 h² a k (k +
  // 1) / 2, exactly up to round-off
  constexpr double kForce = 0.1;  // N
  const Scene scene = HangingJaws(0.03, StillFrame(Vector3d(0, 0, 0.5)), kForce);
  State state = InitialState(scene);
  const double h = scene.h;
  const double a = 2 * kForce / (kJaw0Mass + kJaw1Mass);
  const double gap = 0.06 - kPadSize.x();  // m between the pads' facing sides
  // m, m/s: round-off of coordinates of 0.5 m and of the closed form's sums, far below the
  // solver's bar, which free flight does not use (it is the closed form)
  constexpr double kPositionRoundOff = 1e-15, kSpeedRoundOff = 1e-13;
  int k = 0;
  for (; 2 * h * h * a * (k + 1) * (k + 2) / 2 < gap; ++k) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    const double closed = h * h * a * (k + 1) * (k + 2) / 2;
    EXPECT_NEAR(state.bodies[0].p_WB.x(), -0.03 + closed, kPositionRoundOff) << "k = " << k;
    EXPECT_NEAR(state.bodies[1].p_WB.x(), 0.03 - closed, kPositionRoundOff) << "k = " << k;
    EXPECT_NEAR(state.bodies[0].v_WB.x(), (k + 1) * h * a, kSpeedRoundOff) << "k = " << k;
    // across the axis and in orientation the frame holds them
    for (const BodyState& jaw : state.bodies) {
      EXPECT_NEAR(jaw.p_WB.z(), 0.5, kPositionRoundOff);
      EXPECT_NEAR(jaw.v_WB.z(), 0, kSpeedRoundOff);
      EXPECT_LE(jaw.w_WB.norm(), kSpeedRoundOff);
    }
  }
  ASSERT_GT(k, 10);
  // they meet (an inelastic impact at the centre) and press on each other with the actuator's
  // force: the contact impulse is F h, to the solver's bar on the jaws' impulse scale m V (V ≥
  // the drive h F / m)
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
  const double kImpulseTol = 10 * kSolverTolerance * h * kForce;  // N·s, rows summed
  ASSERT_EQ(scene.contacts.size(), 1u);
  EXPECT_NEAR(state.contacts[0].p_n, kForce * h, kImpulseTol);
  // m: where they meet, to the solver's bar on their velocities times h (≲ 1e-14 m) and the
  // round-off of the contact's coordinates, with a margin
  constexpr double kMeetingTol = 1e-12;
  EXPECT_NEAR(state.bodies[0].p_WB.x() + state.bodies[1].p_WB.x(), 0, kMeetingTol);  // centred
  EXPECT_NEAR(state.bodies[1].p_WB.x() - state.bodies[0].p_WB.x(), kPadSize.x(), kMeetingTol);
}

TEST(GripperTest, JawsFollowTheFramesPathAndTurnAcrossTheAxis) {
  // a frame that moves, tilts and turns through waypoints; the jaws close on nothing with a
  // small force, so along the axis they move too; across it and in orientation each must sit on
  // its place in the frame at every step
  std::vector<Waypoint> path(3);
  path[0].pose.p = Vector3d(0, 0, 0.5);
  path[1].t = 0.5;
  path[1].pose.p = Vector3d(0.1, 0.2, 0.6);
  path[1].pose.q = Quaterniond(Eigen::AngleAxisd(1.0, Vector3d(0.3, 0.2, 1).normalized()));
  path[2].t = 1;
  path[2].pose.p = Vector3d(-0.1, 0.1, 0.5);
  path[2].pose.q = Quaterniond(Eigen::AngleAxisd(-0.5, Vector3d(1, 0, 0.2).normalized()));
  const Scene scene = HangingJaws(0.05, KinematicMotion(path, "test path"), 0.02);
  const Gripper& hand = scene.grippers[0];
  State state = InitialState(scene);
  // m, rad: each step ends on the frame up to the solver's bar on the jaws' velocities (1e-12 of
  // their scale, ≲ 1 m/s, times h) and the round-off of 0.5 m coordinates; the error of a step
  // is corrected in the next, so it never accumulates
  constexpr double kPlaceTol = 1e-13, kTurnTol = 1e-12;
  while (state.t < 1 - scene.h / 2) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    const KinematicPose frame = hand.motion->PoseAt(state.t);
    const Vector3d axis = frame.q * hand.axis;
    Vector3d centre = Vector3d::Zero(), target_centre = Vector3d::Zero();
    for (int j = 0; j < 2; ++j) {
      const BodyState& jaw = state.bodies[j];
      const Vector3d target = frame.p + frame.q * hand.jaw_in_frame[j].p;
      const Vector3d off = jaw.p_WB - target;
      EXPECT_LE((off - axis.dot(off) * axis).norm(), kPlaceTol) << "t = " << state.t;
      EXPECT_LE(jaw.Q_WB.angularDistance(frame.q * hand.jaw_in_frame[j].q), kTurnTol)
          << "t = " << state.t;
      centre += 0.5 * jaw.p_WB;
      target_centre += 0.5 * target;
    }
    EXPECT_LE(std::abs(axis.dot(centre - target_centre)), kPlaceTol) << "t = " << state.t;
  }
}

// ---------------------------------------------------------------------------------------------
// A box on the table between the jaws

constexpr double kBoxMass = 0.2;                // kg
const Vector3d kBoxSize(0.05, 0.05, 0.08);      // m
constexpr double kMuTable = 0.3, kMuPad = 0.8;  // the box on the table; the pads on the box

// the box (body 0) on the ground, the jaws (1, 2) touching its sides at mid-height; the frame
// at the box's centre moves by `motion`
Scene HeldBox(KinematicMotion motion, double force) {
  Body box = MakeBoxBody(kBoxSize, kBoxMass, "box");
  box.p0 = Vector3d(0, 0, kBoxSize.z() / 2);
  const double side = (kBoxSize.x() + kPadSize.x()) / 2;
  Scene scene =
      testing::MakeGroundScene({box, Jaw("jaw0", kJaw0Mass, Vector3d(-side, 0, box.p0.z())),
                                Jaw("jaw1", kJaw1Mass, Vector3d(side, 0, box.p0.z()))},
                               0.01, Friction{kMuTable, 1, 1, 0.02});
  for (Body& body : scene.bodies) body.friction = Friction{kMuPad, 1, 1, 0.01};
  AddBodyPairs(scene);
  // the pads' friction on the box: the pair rule keeps equal bodies' values
  for (const ContactPair& pair : scene.contacts)
    if (pair.WithBody()) {
      EXPECT_DOUBLE_EQ(pair.friction.mu, kMuPad);
    }
  AddHand(scene, std::move(motion), TimeFunction(force), 1, 2);
  scene.duration = 2;
  ValidateScene(scene);
  return scene;
}

// the contact impulse on the box from the pair of `box` and body `jaw` (F is the box: the lower
// index), world
Vector3d ImpulseOnBox(const Scene& scene, const State& state, int jaw) {
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (pair.body != 0 || pair.other_body != jaw) continue;
    const ContactState& c = state.contacts[k];
    return c.p_n * c.n + c.p_t * c.t + c.p_o * c.o;
  }
  ADD_FAILURE() << "no contact of the box with body " << jaw;
  return Vector3d::Zero();
}

KinematicMotion Drag(double speed) {
  ConstantTwist twist;
  twist.start.p = Vector3d(0, 0, kBoxSize.z() / 2);
  twist.v = Vector3d(0, speed, 0);
  return KinematicMotion(twist, "test drag");
}

TEST(GripperTest, AFirmGripDragsTheBoxAtTheFramesSpeedAndThePadsCarryTheTablesFriction) {
  // 2 μ_pad F = 8 N ≫ μ_table m g = 0.59 N: the box sticks to the pads and slides on the table
  constexpr double kSpeed = 0.1, kForce = 5;  // m/s, N
  const Scene scene = HeldBox(Drag(kSpeed), kForce);
  State state = InitialState(scene);
  const double h = scene.h;
  // m/s: the pads stick up to the creep ε = kStickCreepFraction × the island's velocity scale,
  // which the jaws' drive sets (h F / m_0 = 1 m/s); the box's slip on the pads is ε times the
  // friction they carry over their limit, ≤ ε (twice: a margin off the bar)
  const double kCreepBar = 2 * kStickCreepFraction * h * kForce / kJaw0Mass;
  // N·s: the Newton–Euler rows hold to the solver's bar on the impulse scale m V (rows summed)
  const double kImpulseTol = 10 * kSolverTolerance * kJaw1Mass * h * kForce / kJaw0Mass;
  // N·s: but a creeping contact's friction is e² μ p_n v / ε: the slip v holds to a few of the
  // solver's bar τ V (10: the velocity rows it sums, a margin), so the friction only to
  // 10 μ p_n τ V / ε = 10 μ p_n τ / kStickCreepFraction (1.4e-5 of the pulled friction); two pads
  const double kFrictionTol =
      2 * kCreepSlipBars * kMuPad * kForce * h * kSolverTolerance / kStickCreepFraction;
  for (int k = 1; k <= 100; ++k) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    if (k < 5) continue;  // the first steps bring the box up to speed
    const BodyState& box = state.bodies[0];
    EXPECT_NEAR(box.v_WB.y(), kSpeed, kCreepBar) << "t = " << state.t;
    EXPECT_NEAR(box.v_WB.x(), 0, kCreepBar) << "t = " << state.t;
    const Vector3d left = ImpulseOnBox(scene, state, 1), right = ImpulseOnBox(scene, state, 2);
    // each pad presses with the actuator's force (the table's friction acts across the axis)
    EXPECT_NEAR(left.x(), kForce * h, kImpulseTol) << "t = " << state.t;
    EXPECT_NEAR(right.x(), -kForce * h, kImpulseTol) << "t = " << state.t;
    // and together they pull with the table's sliding friction μ m g: at constant speed the
    // box's momentum does not change, the pads carry none of its weight (nothing slides
    // vertically), so the table's normal impulse is m g h
    EXPECT_NEAR((left + right).y(), kMuTable * kBoxMass * kG * h, kFrictionTol)
        << "t = " << state.t;
    EXPECT_NEAR((left + right).z(), 0, kFrictionTol) << "t = " << state.t;
  }
}

TEST(GripperTest, AGripTooWeakForTheTablesFrictionLeavesTheBoxWhereItIs) {
  // 2 μ_pad F = 0.32 N < μ_table m g = 0.59 N: the pads slide along the box, which the table
  // holds; each pad's friction is its limit μ_pad F against the drag
  constexpr double kSpeed = 0.1, kForce = 0.2;  // m/s, N
  const Scene scene = HeldBox(Drag(kSpeed), kForce);
  State state = InitialState(scene);
  const double h = scene.h;
  // m/s: the table sticks up to the creep (island velocity scale: the frame's speed or the
  // jaws' drive h F / m_0 = 0.04 m/s, whichever is larger)
  const double kCreepBar = 2 * kStickCreepFraction * (kSpeed + h * kForce / kJaw0Mass);
  // N·s: the box's balance holds the table's sticking friction, known to μ p_n τ /
  // kStickCreepFraction (as the drag's pads), and so the pads' impulses are
  const double kCreepTol =
      kCreepSlipBars * kMuTable * kBoxMass * kG * h * kSolverTolerance / kStickCreepFraction;
  // 0.3 s: the pads slide 3 cm, still on the box's 5 cm sides (they leave them after 4.5 cm)
  for (int k = 1; k <= 30; ++k) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    const BodyState& box = state.bodies[0];
    EXPECT_LE(box.v_WB.norm(), kCreepBar) << "t = " << state.t;
    EXPECT_LE((box.p_WB - scene.bodies[0].p0).norm(), kCreepBar * state.t) << "t = " << state.t;
    const Vector3d left = ImpulseOnBox(scene, state, 1), right = ImpulseOnBox(scene, state, 2);
    EXPECT_NEAR(left.x(), kForce * h, kCreepTol) << "t = " << state.t;
    EXPECT_NEAR(left.y(), kMuPad * kForce * h, kCreepTol) << "t = " << state.t;
    EXPECT_NEAR(right.y(), kMuPad * kForce * h, kCreepTol) << "t = " << state.t;
  }
}

TEST(GripperTest, AGripThatCarriesTheWeightLiftsTheBoxOffTheTable) {
  // 2 μ_pad F = 8 N > m g = 1.96 N: lifted at 5 cm/s, the box rises with the frame, the table
  // lets go, and the pads carry the weight: m g h in all, half each by symmetry
  constexpr double kSpeed = 0.05, kForce = 5;  // m/s, N
  ConstantTwist lift;
  lift.start.p = Vector3d(0, 0, kBoxSize.z() / 2);
  lift.v = Vector3d(0, 0, kSpeed);
  const Scene scene = HeldBox(KinematicMotion(lift, "test lift"), kForce);
  State state = InitialState(scene);
  const double h = scene.h;
  const double kCreepBar = 2 * kStickCreepFraction * h * kForce / kJaw0Mass;  // as the drag's
  const double kImpulseTol = 10 * kSolverTolerance * kJaw1Mass * h * kForce / kJaw0Mass;
  // N·s: how the pads share the weight is the creep law's, known to μ p_n τ / ε V (the drag's)
  const double kShareTol =
      2 * kCreepSlipBars * kMuPad * kForce * h * kSolverTolerance / kStickCreepFraction;
  for (int k = 1; k <= 100; ++k) {
    const double v_before = state.bodies[0].v_WB.z();
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    if (k < 5) continue;
    const BodyState& box = state.bodies[0];
    EXPECT_NEAR(box.v_WB.z(), kSpeed, kCreepBar) << "t = " << state.t;
    EXPECT_LE(state.contacts[0].p_n, kImpulseTol) << "t = " << state.t;  // box–ground: apart
    const Vector3d left = ImpulseOnBox(scene, state, 1), right = ImpulseOnBox(scene, state, 2);
    // the weight, and the box's change of momentum (its creep on the pads, ≲ 1e-9 m/s a step)
    EXPECT_NEAR((left + right).z(), kBoxMass * (kG * h + box.v_WB.z() - v_before), kImpulseTol)
        << "t = " << state.t;
    EXPECT_NEAR(left.z(), right.z(), kShareTol) << "t = " << state.t;
  }
  EXPECT_GT(state.bodies[0].p_WB.z(), kBoxSize.z() / 2 + 0.9 * kSpeed * 1.0);
}

TEST(GripperTest, JawsOverTheTableLeaveItOutOfTheirIsland) {
  // the pads hang 2.5 cm over the table: a 5 N grip closes a 50 g jaw by at most h² F / m =
  // 1 mm a step, along the axis only, and the frame holds it across; the table is out of their
  // reach, and the island's Newton system has no blocks for it (the box keeps its own)
  const Scene scene = HeldBox(Drag(0.1), 5);
  State state = InitialState(scene);
  for (int k = 0; k < 10; ++k) ASSERT_TRUE(Step(scene, state).converged);
  const std::vector<Island> islands = FormIslands(scene, state);
  ASSERT_EQ(islands.size(), 1u);
  EXPECT_EQ(islands[0].bodies, (std::vector<int>{0, 1, 2}));
  bool box_on_table = false;
  for (int k : islands[0].contacts) {
    const ContactPair& pair = scene.contacts[k];
    if (pair.WithBody()) continue;
    EXPECT_EQ(pair.body, 0) << "the table is in the island of jaw " << pair.body;
    box_on_table |= pair.body == 0;
  }
  EXPECT_TRUE(box_on_table);
}

TEST(GripperTest, TrajectoryRowsCarryTheGripsOpeningAndForce) {
  const Scene scene = HeldBox(Drag(0.1), 5);
  State state = InitialState(scene);
  StepReport report;
  for (int k = 0; k < 20; ++k) report = Step(scene, state);
  const std::vector<std::string> columns = TrajectoryColumns(scene);
  const std::vector<double> values = TrajectoryValues(scene, state, report);
  ASSERT_EQ(columns.size(), values.size());
  const auto value = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << name;
    return it == columns.end() ? NAN : values[it - columns.begin()];
  };
  // closed on the 5 cm box: the pads' centres one pad thickness further apart (m: to the
  // solver's bar on the jaws' velocities times h and the coordinates' round-off)
  constexpr double kOpeningTol = 1e-12;
  EXPECT_NEAR(value("hand.width"), kBoxSize.x() + kPadSize.x(), kOpeningTol);
  EXPECT_EQ(value("hand.force"), 5);
}

TEST(GripperTest, OnlyTheHullModelStepsAGripper) {
  Scene scene = HeldBox(Drag(0.1), 1);
  scene.model = ContactModel::kPoint;
  State state = InitialState(scene);
  EXPECT_THROW(Step(scene, state), ModelInvalid);
}

TEST(GripperTest, ANegativeForceDuringTheRunIsAnInputErrorNamingTheGripperAndTime) {
  Scene scene = HeldBox(Drag(0.1), 1);
  scene.grippers[0].force = TimeFunction("t < 0.05 ? 1 : -1", "test force");
  State state = InitialState(scene);
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(Step(scene, state).converged);
  try {
    Step(scene, state);
    FAIL() << "a negative force ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gripper 'hand': force = -1 N at t = 0.05"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ecpsim::engine
