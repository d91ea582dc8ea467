// The harness of the rotation-invariance checks: TurnedAboutZ (tests/engine/turned_scene.h)
// turns every world-frame quantity of a loaded scene, the turn by 0 is the identity and four
// quarter turns give the scene back.

#include "tests/engine/turned_scene.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"
#include "tests/engine/trajectory_hash.h"
#include "tests/engine/turned_deviation.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// every world-frame quantity a scene file can hold, none of them along a world axis: a body
// moving and spinning under a force at a point, a torque and an impulse; a box fixture and a
// tilted plane; kinematic bodies by waypoints, by rpy and axis-angle expressions and by a
// constant twist; a gripper whose frame follows waypoints and turns
constexpr const char* kAllKinds = R"yaml(
h: 0.01
duration: 1
ground: {friction: {mu: 0.5, e_t: 1, e_o: 1, e_r: 0.02}}
obstacles:
  - {name: wall, box: {size: [0.1, 0.4, 0.2], position: [0.8, 0.3, 0.1], rpy: [0, 0, 20]}}
  - {name: slope, plane: {normal: [0.1, 0.2, 1], offset: -0.5}}
bodies:
  - name: block
    shape: {box: {size: [0.1, 0.08, 0.06]}}
    mass: 0.5
    position: [0.2, -0.1, 0.3]
    rpy: [10, 20, 30]
    velocity: [0.3, -0.2, 0.1]
    angular_velocity: [1, 2, 3]
  - name: finger
    kinematic: true
    shape: {cylinder: {radius: 0.01, length: 0.04}}
    motion:
      waypoints:
        - {t: 0, position: [-0.3, 0.2, 0.5]}
        - {t: 1, position: [-0.2, 0.25, 0.5], rpy: [0, 0, 40]}
  - name: wand
    kinematic: true
    shape: {box: {size: [0.02, 0.02, 0.1]}}
    motion:
      expressions: {position: ["0.1*t", "0.02*sin(2*pi*t)", 0.6], rpy: [5, "10*t", "30*t"]}
  - name: spinner
    kinematic: true
    shape: {box: {size: [0.02, 0.05, 0.02]}}
    motion:
      expressions: {position: [-0.5, 0.1, 0.6], axis_angle: {axis: [0, 0, -1], angle: "0.5*t"}}
  - name: plate
    kinematic: true
    shape: {box: {size: [0.2, 0.2, 0.01]}}
    motion:
      velocity:
        {position: [0.4, -0.4, 0.7], rpy: [0, 10, 0], linear: [0.1, 0.2, -0.05],
         angular: [0.3, 0, 0.5]}
  - {name: box, shape: {box: {size: [0.05, 0.05, 0.08]}}, mass: 0.2, position: [-0.6, 0.5, 0.04]}
  - {name: left_jaw, shape: {box: {size: [0.01, 0.04, 0.03]}}, mass: 0.05,
     position: [-0.65, 0.5, 0.04]}
  - {name: right_jaw, shape: {box: {size: [0.01, 0.04, 0.03]}}, mass: 0.05,
     position: [-0.55, 0.5, 0.04]}
grippers:
  - name: hand
    jaws: [left_jaw, right_jaw]
    axis: [1, 0, 0]
    force: "t < 0.3 ? 0.2 : 5"
    motion:
      waypoints:
        - {t: 0.2, position: [-0.6, 0.5, 0.04]}
        - {t: 0.8, position: [-0.6, 0.6, 0.04], rpy: [0, 0, 30]}
loads:
  - {body: block, force: ["2*sin(t)", 1.5, -0.3], at: [0.01, 0.02, 0]}
  - {body: block, torque: [0.1, "0.2*t", 0.05]}
impulses:
  - {body: block, time: 0.1, linear: [0.05, 0.02, 0.01], angular: [0.001, 0, 0.01]}
)yaml";

// times at which functions of time and motions are compared: before, inside and after the
// waypoints and load windows
const double kTimes[] = {0, 0.137, 0.5, 0.81, 1.3};

// a turn of O(1) vectors rounds each coordinate once or twice (c x − s y): a few ulps of 1
constexpr double kTurnRoundOff = 8 * std::numeric_limits<double>::epsilon();
// rad: four quarter turns of an orientation multiply by the rounded √½ four times and normalize
// (waypoints); expressions add 90° four times to a yaw and convert 360° more to radians: a few
// ulps of 2π
constexpr double kQuarterTurnsOrientation = 16 * std::numeric_limits<double>::epsilon();

Scene AllKindsScene() {
  const fs::path path =
      fs::temp_directory_path() / ("turned_all_kinds_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << kAllKinds;
  Scene scene = LoadScene(path.string()).scene;
  fs::remove(path);
  return scene;
}

// rad: the angle between two orientations, shortest arc (either sign of either quaternion)
double AngleBetween(const Quaterniond& a, const Quaterniond& b) {
  return QuaternionLog(a.conjugate() * b).norm();
}

// a world-frame vector function of time: (x, y, z)(t)
Vector3d At(const TimeFunction& x, const TimeFunction& y, const TimeFunction& z, double t) {
  return Vector3d(x(t), y(t), z(t));
}

std::vector<std::string> HashesOf(const Scene& scene, int steps) {
  State state = InitialState(scene);
  std::vector<std::string> hashes;
  for (int k = 0; k < steps; ++k) {
    const StepReport report = Step(scene, state);
    hashes.push_back(std::to_string(testing::HashStep(state, report)));
  }
  return hashes;
}

TEST(TurnedSceneTest, TurnByZeroOrAWholeTurnRunsBitIdentical) {
  // 0.3 s of the scene of every kind (the gripper closes) and of each shipped multi-body scene
  constexpr int kSteps = 30;
  std::vector<std::pair<std::string, Scene>> scenes = {{"all kinds", AllKindsScene()}};
  const std::string dir = std::string(ECPSIM_SOURCE_DIR) + "/scenes";
  for (const std::string& name : testing::MultiBodyScenes(dir)) {
    scenes.emplace_back(name, LoadScene(dir + "/" + name).scene);
  }
  for (const auto& [name, scene] : scenes) {
    const std::vector<std::string> expected = HashesOf(scene, kSteps);
    // 2π / (π/2) is 4 exactly: a whole number of quarter turns
    for (const double angle : {0.0, -0.0, 2 * M_PI}) {
      EXPECT_EQ(HashesOf(testing::TurnedAboutZ(scene, angle), kSteps), expected)
          << name << ", turned by " << angle;
    }
  }
}

TEST(TurnedSceneTest, FourQuarterTurnsGiveTheSceneBack) {
  const Scene scene = AllKindsScene();
  Scene back = scene;
  for (int k = 0; k < 4; ++k) back = testing::TurnedAboutZ(back, M_PI / 2);

  // vectors: permuted and negated four times, bit for bit
  EXPECT_EQ(back.gravity, scene.gravity);
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& a = scene.bodies[i];
    const Body& b = back.bodies[i];
    EXPECT_EQ(b.p0, a.p0) << a.name;
    EXPECT_EQ(b.v0, a.v0) << a.name;
    EXPECT_EQ(b.w0, a.w0) << a.name;
    EXPECT_LE(AngleBetween(b.q0, a.q0), kQuarterTurnsOrientation) << a.name;
    if (!a.IsKinematic()) continue;
    for (const double t : kTimes) {
      EXPECT_EQ(b.motion->PoseAt(t).p, a.motion->PoseAt(t).p) << a.name << " at " << t;
      EXPECT_LE(AngleBetween(b.motion->PoseAt(t).q, a.motion->PoseAt(t).q),
                kQuarterTurnsOrientation)
          << a.name << " at " << t;
    }
  }
  for (size_t i = 0; i < scene.obstacles.size(); ++i) {
    const geometry::ConvexHull& a = scene.obstacles[i].shape->AsPolyhedron()->hull();
    const geometry::ConvexHull& b = back.obstacles[i].shape->AsPolyhedron()->hull();
    EXPECT_EQ(b.vertices, a.vertices) << scene.obstacles[i].name;
    EXPECT_EQ(b.normals, a.normals) << scene.obstacles[i].name;
    EXPECT_EQ(b.offsets, a.offsets) << scene.obstacles[i].name;
  }
  for (size_t i = 0; i < scene.loads.size(); ++i) {
    const Load& a = scene.loads[i];
    const Load& b = back.loads[i];
    for (const double t : kTimes) EXPECT_EQ(At(b.x, b.y, b.z, t), At(a.x, a.y, a.z, t)) << t;
  }
  EXPECT_EQ(back.impulses[0].linear, scene.impulses[0].linear);
  EXPECT_EQ(back.impulses[0].angular, scene.impulses[0].angular);
  for (const double t : kTimes) {
    const KinematicPose a = scene.grippers[0].motion->PoseAt(t);
    const KinematicPose b = back.grippers[0].motion->PoseAt(t);
    EXPECT_EQ(b.p, a.p) << t;
    EXPECT_LE(AngleBetween(b.q, a.q), kQuarterTurnsOrientation) << t;
  }
}

TEST(TurnedSceneTest, TurnsEveryKindOfQuantity) {
  const Scene scene = AllKindsScene();
  for (const double angle : {M_PI / 2, 37 * M_PI / 180, -2.0}) {
    const Scene turned = testing::TurnedAboutZ(scene, angle);
    const Eigen::AngleAxisd turn(angle, Vector3d::UnitZ());
    const Eigen::Matrix3d R = turn.toRotationMatrix();
    const auto near = [](const Vector3d& a, const Vector3d& b) {
      return (a - b).norm() <= kTurnRoundOff * (1 + b.norm());
    };
    SCOPED_TRACE(::testing::Message() << "turned by " << angle << " rad");

    // gravity along z stays
    EXPECT_TRUE(near(turned.gravity, scene.gravity));
    // a body: its initial pose and velocities; its body-frame hull stays
    const Body& block = scene.bodies[0];
    const Body& turned_block = turned.bodies[0];
    EXPECT_TRUE(near(turned_block.p0, R * block.p0));
    EXPECT_TRUE(near(turned_block.v0, R * block.v0));
    EXPECT_TRUE(near(turned_block.w0, R * block.w0));
    EXPECT_LE(AngleBetween(turned_block.q0, Quaterniond(turn) * block.q0), kTurnRoundOff);
    EXPECT_EQ(turned_block.hull, block.hull);
    // loads, a force at a point (body frame, stays) and a torque, as functions of time
    for (size_t i = 0; i < scene.loads.size(); ++i) {
      const Load& a = scene.loads[i];
      const Load& b = turned.loads[i];
      EXPECT_EQ(b.point_B, a.point_B);
      for (const double t : kTimes) {
        EXPECT_TRUE(near(At(b.x, b.y, b.z, t), R * At(a.x, a.y, a.z, t)))
            << "load " << i << " at " << t;
      }
    }
    EXPECT_TRUE(near(turned.impulses[0].linear, R * scene.impulses[0].linear));
    EXPECT_TRUE(near(turned.impulses[0].angular, R * scene.impulses[0].angular));
    // fixtures: the box's corners and face normals, the plane's normal; offsets stay
    for (size_t i = 0; i < scene.obstacles.size(); ++i) {
      const geometry::ConvexHull& a = scene.obstacles[i].shape->AsPolyhedron()->hull();
      const geometry::ConvexHull& b = turned.obstacles[i].shape->AsPolyhedron()->hull();
      ASSERT_EQ(b.vertices.size(), a.vertices.size());
      for (size_t v = 0; v < a.vertices.size(); ++v) {
        EXPECT_TRUE(near(b.vertices[v], R * a.vertices[v])) << scene.obstacles[i].name;
      }
      for (size_t f = 0; f < a.normals.size(); ++f) {
        EXPECT_TRUE(near(b.normals[f], R * a.normals[f])) << scene.obstacles[i].name;
      }
      EXPECT_EQ(b.offsets, a.offsets);
    }
    // kinematic bodies, each form: waypoints, rpy and axis-angle expressions, constant twist
    for (size_t i = 1; i < scene.bodies.size(); ++i) {
      if (!scene.bodies[i].IsKinematic()) continue;
      for (const double t : kTimes) {
        const KinematicPose a = scene.bodies[i].motion->PoseAt(t);
        const KinematicPose b = turned.bodies[i].motion->PoseAt(t);
        EXPECT_TRUE(near(b.p, R * a.p)) << scene.bodies[i].name << " at " << t;
        EXPECT_LE(AngleBetween(b.q, Quaterniond(turn) * a.q), kTurnRoundOff)
            << scene.bodies[i].name << " at " << t;
      }
    }
    // a gripper: its frame's pose and closing axis; the axis in the frame and the jaws'
    // places on it stay
    const Gripper& hand = scene.grippers[0];
    const Gripper& turned_hand = turned.grippers[0];
    EXPECT_EQ(turned_hand.axis, hand.axis);
    for (int jaw = 0; jaw < 2; ++jaw) {
      EXPECT_EQ(turned_hand.jaw_in_frame[jaw].p, hand.jaw_in_frame[jaw].p);
    }
    for (const double t : kTimes) {
      const KinematicPose a = hand.motion->PoseAt(t);
      const KinematicPose b = turned_hand.motion->PoseAt(t);
      EXPECT_TRUE(near(b.p, R * a.p)) << t;
      EXPECT_TRUE(near(ClosingAxis(turned_hand, b), R * ClosingAxis(hand, a))) << t;
      EXPECT_EQ(turned_hand.force(t), hand.force(t));
    }
  }
}

TEST(TurnedSceneDeathTest, AnAxisAngleMotionAboutATiltedAxisCannotBeTurned) {
  // R Exp(a n) = Exp(a R n) R is no turn about one fixed axis: the harness refuses it loudly
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  Scene scene = AllKindsScene();
  PoseExpressions tilted;
  tilted.position = {TimeFunction(0.1), TimeFunction(0.2), TimeFunction(0.3)};
  tilted.orientation = PoseExpressions::Orientation::kAxisAngle;
  tilted.axis = Vector3d(1, 0, 1);
  tilted.angle = TimeFunction("0.5*t", "test");
  scene.bodies[1].motion = std::make_shared<KinematicMotion>(tilted, "test");
  EXPECT_DEATH(testing::TurnedAboutZ(scene, 0.3), "axis");
}

}  // namespace
}  // namespace ecpsim::engine
