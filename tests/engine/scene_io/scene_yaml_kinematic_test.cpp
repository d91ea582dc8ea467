// A kinematic body's `motion:` read from YAML snippets by the loader's reader (not yet part of
// a scene's schema).

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml_reader.h"

namespace ecpsim::engine::yaml {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kEps = std::numeric_limits<double>::epsilon();
// rotation-matrix entries (O(1)) from degrees or quaternions typed in the YAML, a few dozen
// flops away: a few ulps
constexpr double kRotationRoundOff = 16 * kEps;

// the `motion` of a snippet, read as bodies[0].motion of scene.yaml
KinematicMotion ReadSnippet(const std::string& text) {
  const Context ctx{"scene.yaml", ".", {}};
  const YAML::Node root = YAML::Load(text);
  return ReadMotion(ctx, root["motion"], "bodies[0].motion");
}

double MatrixDistance(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return (a.toRotationMatrix() - b.toRotationMatrix()).cwiseAbs().maxCoeff();
}

Eigen::Quaterniond AboutZ(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

// ---- the three forms -------------------------------------------------------------------------

TEST(SceneYamlKinematicTest, ReadsExpressionsWithRpyInDegrees) {
  const KinematicMotion motion = ReadSnippet(R"yaml(motion:
  expressions:
    position: ["0.3*cos(2*t)", "0.3*sin(2*t)", 0.05]
    rpy: [0, 0, "90*t"]
)yaml");
  const KinematicPose pose = motion.PoseAt(1);
  EXPECT_EQ(pose.p, Eigen::Vector3d(0.3 * std::cos(2.0), 0.3 * std::sin(2.0), 0.05));
  EXPECT_LT(MatrixDistance(pose.q, AboutZ(M_PI / 2)), kRotationRoundOff);
}

TEST(SceneYamlKinematicTest, ReadsExpressionsWithAxisAngleInRadians) {
  const KinematicMotion motion = ReadSnippet(R"yaml(motion:
  expressions:
    position: [0, 0, 0.1]
    axis_angle: {axis: [0, 0, 2], angle: "0.5*t"}
)yaml");
  const KinematicPose pose = motion.PoseAt(2);
  EXPECT_EQ(pose.p, Eigen::Vector3d(0, 0, 0.1));
  EXPECT_LT(MatrixDistance(pose.q, AboutZ(1)), kRotationRoundOff);
}

TEST(SceneYamlKinematicTest, ReadsWaypoints) {
  const KinematicMotion motion = ReadSnippet(R"yaml(motion:
  waypoints:
    - {t: 0, position: [0, 0, 0.1]}
    - {t: 2, position: [0.4, 0, 0.1], rpy: [0, 0, 90]}
    - {t: 3, position: [0.4, 0.2, 0.1], quaternion: [0, 0, 0, 2]}
)yaml");
  // half-way through the first segment: half its travel and half its 90° yaw
  const KinematicPose middle = motion.PoseAt(1);
  EXPECT_LT((middle.p - Eigen::Vector3d(0.2, 0, 0.1)).norm(), 4 * kEps);
  EXPECT_LT(MatrixDistance(middle.q, AboutZ(M_PI / 4)), kRotationRoundOff);
  // the last waypoint's quaternion, normalized: 180° about z, held afterwards
  const KinematicPose last = motion.PoseAt(5);
  EXPECT_EQ(last.p, Eigen::Vector3d(0.4, 0.2, 0.1));
  EXPECT_LT(MatrixDistance(last.q, AboutZ(M_PI)), kRotationRoundOff);
}

TEST(SceneYamlKinematicTest, ReadsAConstantTwist) {
  const KinematicMotion motion = ReadSnippet(R"yaml(motion:
  velocity:
    position: [0, 0, 0.1]
    rpy: [0, 0, 30]
    linear: [0.1, 0, 0]
    angular: [0, 0, 0.5]
)yaml");
  const KinematicMotion::Twist twist = motion.StepTwist(0, 0.01);
  EXPECT_EQ(twist.v, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_EQ(twist.w, Eigen::Vector3d(0, 0, 0.5));
  const KinematicPose pose = motion.PoseAt(2);
  EXPECT_EQ(pose.p, Eigen::Vector3d(0.2, 0, 0.1));
  EXPECT_LT(MatrixDistance(pose.q, AboutZ(M_PI / 6 + 1)), kRotationRoundOff);
}

TEST(SceneYamlKinematicTest, AConstantTwistDefaultsToRest) {
  const KinematicMotion motion = ReadSnippet(R"yaml(motion:
  velocity: {position: [1, 2, 3]}
)yaml");
  EXPECT_EQ(motion.PoseAt(7).p, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(motion.StepTwist(7, 0.01).v, Eigen::Vector3d::Zero());
  EXPECT_EQ(motion.StepTwist(7, 0.01).w, Eigen::Vector3d::Zero());
}

TEST(SceneYamlKinematicTest, TheFormatsExampleReads) {
  // the first yaml block of docs/scene_format.md's "Kinematic bodies": each body's motion
  std::ifstream file(std::string(ECPSIM_SOURCE_DIR) + "/docs/scene_format.md");
  std::stringstream text;
  text << file.rdbuf();
  const std::string doc = text.str();
  const size_t section = doc.find("## Kinematic bodies");
  ASSERT_NE(section, std::string::npos);
  const size_t begin = doc.find("```yaml\n", section);
  ASSERT_NE(begin, std::string::npos);
  const size_t end = doc.find("```", begin + 8);
  const YAML::Node root = YAML::Load(doc.substr(begin + 8, end - begin - 8));
  const Context ctx{"docs/scene_format.md", ".", {}};
  ASSERT_EQ(root["bodies"].size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const KinematicMotion motion =
        ReadMotion(ctx, root["bodies"][i]["motion"], Index("bodies", i) + ".motion");
    EXPECT_TRUE(root["bodies"][i]["kinematic"].as<bool>());
    // every example moves (or turns) between t = 0 and 1 s, at less than half a turn per step
    const KinematicMotion::Twist twist = motion.StepTwist(0.5, 0.01);
    EXPECT_GT(twist.v.norm() + twist.w.norm(), 0) << "bodies[" << i << "]";
  }
}

// ---- errors: file:line:col, key, value, expected ---------------------------------------------

struct BadMotion {
  const char* yaml;
  const char* message;
};

TEST(SceneYamlKinematicTest, BadMotionsNameLineKeyValueAndExpected) {
  const std::vector<BadMotion> cases = {
      // the form
      {"motion: [1, 2]\n",
       "scene.yaml:1:9: bodies[0].motion = [1, 2]: expected a mapping with keys expressions, "
       "waypoints, velocity"},
      {"motion: {}\n", "scene.yaml:1:9: bodies[0].motion = {}: expected exactly one of"},
      {"motion:\n  velocity: {position: [0, 0, 0]}\n  waypoints: [{t: 0, position: [0, 0, 0]}]\n",
       "scene.yaml:2:3: bodies[0].motion = {velocity: {position: [0, 0, 0]}, waypoints: [{t: 0, "
       "posi...: expected exactly one of `expressions: {position, rpy | axis_angle}`"},
      {"motion:\n  waypoint: []\n",
       "scene.yaml:2:3: bodies[0].motion.waypoint: unknown key (did you mean \"waypoints\"?); "
       "expected one of expressions, waypoints, velocity"},
      // expressions
      {"motion:\n  expressions:\n    rpy: [0, 0, 0]\n",
       "scene.yaml:3:5: bodies[0].motion.expressions.position = (missing): expected [x, y, z] (m, "
       "world frame)"},
      {"motion:\n  expressions:\n    position: [0, 0]\n",
       "scene.yaml:3:15: bodies[0].motion.expressions.position = [0, 0]: expected a list of 3 "
       "components ([x, y, z] in m, world frame), each a number or an expression of t"},
      {"motion:\n  expressions:\n    position: [\"sin(\", 0, 0]\n",
       "scene.yaml:3:16: bodies[0].motion.expressions.position[0] = \"sin(\": "},
      {"motion:\n  expressions:\n    position: [0, \"x*t\", 0]\n",
       "scene.yaml:3:19: bodies[0].motion.expressions.position[1] = \"x*t\": "},
      {"motion:\n  expressions:\n    position: [0, 0, 0]\n    rpy: [0, .nan, 0]\n",
       "scene.yaml:4:14: bodies[0].motion.expressions.rpy[1] = .nan: expected a finite number or "
       "an expression of t"},
      {"motion:\n  expressions:\n    position: [0, 0, 0]\n    rpy: [0, 0, 0]\n"
       "    axis_angle: {axis: [0, 0, 1], angle: 1}\n",
       "scene.yaml:5:17: bodies[0].motion.expressions.axis_angle = {axis: [0, 0, 1], angle: 1}: "
       "expected either `rpy` or `axis_angle`, not both"},
      {"motion:\n  expressions:\n    position: [0, 0, 0]\n"
       "    axis_angle: {axis: [0, 0, 0], angle: \"t\"}\n",
       "scene.yaml:4:24: bodies[0].motion.expressions.axis_angle.axis = [0, 0, 0]: expected a "
       "non-zero axis [x, y, z] (it is normalized)"},
      {"motion:\n  expressions:\n    position: [0, 0, 0]\n    axis_angle: {axis: [0, 0, 1]}\n",
       "scene.yaml:4:17: bodies[0].motion.expressions.axis_angle.angle = (missing): expected the "
       "angle (rad), a number or an expression of t"},
      // waypoints
      {"motion:\n  waypoints: []\n",
       "scene.yaml:2:14: bodies[0].motion.waypoints = []: expected a list of at least one "
       "waypoint"},
      {"motion:\n  waypoints: {t: 0}\n",
       "scene.yaml:2:14: bodies[0].motion.waypoints = {t: 0}: expected a list of at least one "
       "waypoint"},
      {"motion:\n  waypoints:\n    - {t: 0, positon: [0, 0, 0]}\n",
       "scene.yaml:3:14: bodies[0].motion.waypoints[0].positon: unknown key (did you mean "
       "\"position\"?)"},
      {"motion:\n  waypoints:\n    - {t: .nan, position: [0, 0, 0]}\n",
       "scene.yaml:3:11: bodies[0].motion.waypoints[0].t = .nan: expected a finite time (s)"},
      {"motion:\n  waypoints:\n    - {t: 0, position: [0, 0, 0]}\n    - {t: 0, position: [1, 0, "
       "0]}\n",
       "scene.yaml:4:11: bodies[0].motion.waypoints[1].t = 0: expected a time > 0 s, the time of "
       "bodies[0].motion.waypoints[0] (strictly increasing)"},
      {"motion:\n  waypoints:\n    - {t: 0, position: [0, 0, 0], quaternion: [0, 0, 0, 0]}\n",
       "scene.yaml:3:47: bodies[0].motion.waypoints[0].quaternion = [0, 0, 0, 0]: expected a "
       "non-zero quaternion"},
      {"motion:\n  waypoints:\n    - {t: 0, position: [0, 0, 0], rpy: [0, 0, 0]}\n"
       "    - {t: 1, position: [0, 0, 0], rpy: [0, 0, 180]}\n",
       "scene.yaml:4:40: bodies[0].motion.waypoints[1].rpy = [0, 0, 180]: expected an orientation "
       "less than half a turn from bodies[0].motion.waypoints[0]'s"},
      // a constant twist
      {"motion:\n  velocity: {linear: [1, 0, 0]}\n",
       "scene.yaml:2:13: bodies[0].motion.velocity.position = (missing): expected [x, y, z] (m) "
       "at t = 0, world frame"},
      {"motion:\n  velocity:\n    position: [0, 0, 0]\n    linear: [1, 0]\n",
       "scene.yaml:4:13: bodies[0].motion.velocity.linear = [1, 0]: expected a list of 3 finite "
       "numbers [x, y, z] (m/s, world frame)"},
      {"motion:\n  velocity:\n    position: [0, 0, 0]\n    angular: [0, 0, .inf]\n",
       "scene.yaml:4:21: bodies[0].motion.velocity.angular[2] = .inf: expected a list of 3 "
       "finite numbers [x, y, z] (rad/s, world frame)"},
  };
  for (const BadMotion& c : cases) {
    EXPECT_THAT([&] { ReadSnippet(c.yaml); }, ThrowsMessage<InputError>(HasSubstr(c.message)))
        << c.yaml;
  }
}

TEST(SceneYamlKinematicTest, ErrorsDuringTheRunNameTheMotion) {
  const KinematicMotion spin = ReadSnippet(R"yaml(motion:
  velocity:
    position: [0, 0, 0]
    angular: [0, 0, 400]
)yaml");
  EXPECT_THAT([&] { spin.StepTwist(0, 0.01); },
              ThrowsMessage<InputError>(HasSubstr(
                  "scene.yaml:2:3: bodies[0].motion: the step from t = 0 s to 0.01 s (h = 0.01 "
                  "s) turns the body by |ω| h = 4 rad")));
  const KinematicMotion pole = ReadSnippet(R"yaml(motion:
  expressions:
    position: ["1/(t-1)", 0, 0]
)yaml");
  EXPECT_THAT([&] { pole.PoseAt(1); },
              ThrowsMessage<InputError>(HasSubstr(
                  "scene.yaml:3:16: bodies[0].motion.expressions.position[0] = \"1/(t-1)\" at t = "
                  "1 s evaluates to inf")));
}

}  // namespace
}  // namespace ecpsim::engine::yaml
