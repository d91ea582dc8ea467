// Prescribed motion in the scene format: a kinematic body's (or a gripper frame's) `motion:` as
// expressions of t, waypoints or a constant twist (docs/scene_format.md, "Kinematic bodies"),
// and the grippers that carry their jaws on such a frame ("Grippers").

#include <cmath>

#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml_reader.h"

namespace ecpsim::engine::yaml {
namespace {

// [x, y, z], each a number or an expression of t
std::array<TimeFunction, 3> ReadTimeFunctions3(const Context& ctx, const YAML::Node& node,
                                               const std::string& key, const std::string& unit) {
  if (!node.IsSequence() || node.size() != 3) {
    Fail(ctx, node, key,
         fmt::format("a list of 3 components ({}), each a number or an expression of t", unit));
  }
  return {ReadTimeFunction(ctx, node[0], Index(key, 0)),
          ReadTimeFunction(ctx, node[1], Index(key, 1)),
          ReadTimeFunction(ctx, node[2], Index(key, 2))};
}

// `expressions: {position, rpy | axis_angle}`
PoseExpressions ReadExpressions(const Context& ctx, const YAML::Node& node,
                                const std::string& key) {
  const MapNode map(ctx, node, key, {"position", "rpy", "axis_angle"});
  PoseExpressions expressions;
  const YAML::Node position =
      map.Require("position", "[x, y, z] (m, world frame), each a number or an expression of t");
  expressions.position =
      ReadTimeFunctions3(ctx, position, map.Key("position"), "[x, y, z] in m, world frame");
  if (map.Has("rpy") && map.Has("axis_angle")) {
    map.FailAt("axis_angle", "either `rpy` or `axis_angle`, not both");
  }
  if (map.Has("rpy")) {
    expressions.rpy_deg =
        ReadTimeFunctions3(ctx, map.Get("rpy"), map.Key("rpy"), "[roll, pitch, yaw] in degrees");
  } else if (map.Has("axis_angle")) {
    const MapNode axis_angle(ctx, map.Get("axis_angle"), map.Key("axis_angle"), {"axis", "angle"});
    expressions.orientation = PoseExpressions::Orientation::kAxisAngle;
    expressions.axis =
        ReadVector3(ctx, axis_angle.Require("axis", "[x, y, z], the world axis of the turn"),
                    axis_angle.Key("axis"), "a direction, world frame");
    if (expressions.axis.norm() < kMinRotationAxisLength) {
      axis_angle.FailAt("axis", "a non-zero axis [x, y, z] (it is normalized)");
    }
    expressions.angle = ReadTimeFunction(
        ctx, axis_angle.Require("angle", "the angle (rad), a number or an expression of t"),
        axis_angle.Key("angle"));
  }
  return expressions;
}

// `waypoints: [{t, position, rpy | quaternion}, ...]`, times strictly increasing
std::vector<Waypoint> ReadWaypoints(const Context& ctx, const YAML::Node& node,
                                    const std::string& key) {
  if (!node.IsSequence() || node.size() == 0) {
    Fail(ctx, node, key,
         "a list of at least one waypoint {t: s, position: [x, y, z], rpy | quaternion}");
  }
  std::vector<Waypoint> waypoints;
  for (size_t i = 0; i < node.size(); ++i) {
    const MapNode map(ctx, node[i], Index(key, i), {"t", "position", "rpy", "quaternion"});
    Waypoint w;
    w.t = ReadNumber(ctx, map.Require("t", "the waypoint's time (s)"), map.Key("t"),
                     "a finite time (s)");
    w.pose.p = ReadVector3(ctx, map.Require("position", "[x, y, z] (m, world frame)"),
                           map.Key("position"), "m, world frame");
    w.pose.q = ReadOrientation(ctx, map);
    if (i > 0) {
      const Waypoint& previous = waypoints.back();
      if (!(w.t > previous.t)) {
        map.FailAt("t", fmt::format("a time > {} s, the time of {} (strictly increasing)",
                                    previous.t, Index(key, i - 1)));
      }
      const double turn = QuaternionLog(w.pose.q * previous.pose.q.conjugate()).norm();
      if (turn >= kMaxKinematicTurn) {
        map.FailAt(map.Has("quaternion") ? "quaternion" : "rpy",
                   fmt::format("an orientation less than half a turn from {}'s (this one is "
                               "{:.9g} rad away, and at π the shortest arc has no direction); "
                               "add a waypoint in between",
                               Index(key, i - 1), turn));
      }
    }
    waypoints.push_back(w);
  }
  return waypoints;
}

// `velocity: {position, rpy | quaternion, linear, angular}`
ConstantTwist ReadConstantTwist(const Context& ctx, const YAML::Node& node,
                                const std::string& key) {
  const MapNode map(ctx, node, key, {"position", "rpy", "quaternion", "linear", "angular"});
  ConstantTwist twist;
  twist.start.p = ReadVector3(ctx, map.Require("position", "[x, y, z] (m) at t = 0, world frame"),
                              map.Key("position"), "m, world frame, at t = 0");
  twist.start.q = ReadOrientation(ctx, map);
  if (map.Has("linear")) {
    twist.v = ReadVector3(ctx, map.Get("linear"), map.Key("linear"), "m/s, world frame");
  }
  if (map.Has("angular")) {
    twist.w = ReadVector3(ctx, map.Get("angular"), map.Key("angular"), "rad/s, world frame");
  }
  return twist;
}

}  // namespace

KinematicMotion ReadMotion(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key, {"expressions", "waypoints", "velocity"});
  const int forms = map.Has("expressions") + map.Has("waypoints") + map.Has("velocity");
  if (forms != 1) {
    Fail(ctx, node, key,
         "exactly one of `expressions: {position, rpy | axis_angle}`, `waypoints: [{t, "
         "position, rpy | quaternion}, ...]` or `velocity: {position, linear, angular}`");
  }
  const std::string where = fmt::format("{}: {}", Where(ctx, node, key), key);
  if (map.Has("expressions")) {
    return KinematicMotion(ReadExpressions(ctx, map.Get("expressions"), map.Key("expressions")),
                           where);
  }
  if (map.Has("waypoints")) {
    return KinematicMotion(ReadWaypoints(ctx, map.Get("waypoints"), map.Key("waypoints")), where);
  }
  return KinematicMotion(ReadConstantTwist(ctx, map.Get("velocity"), map.Key("velocity")), where);
}

Gripper ReadGripper(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const Scene& scene) {
  const MapNode map(ctx, node, key, {"name", "jaws", "motion", "axis", "force"});
  Gripper gripper;
  gripper.name = map.Has("name") ? ReadName(ctx, map.Get("name"), map.Key("name"))
                                 : fmt::format("gripper{}", scene.grippers.size());
  const YAML::Node jaws = map.Require(
      "jaws", "[A, B]: the names of the two jaw bodies, A closing along +axis towards B");
  if (!jaws.IsSequence() || jaws.size() != 2) {
    Fail(ctx, jaws, map.Key("jaws"),
         "[A, B]: the names of the two jaw bodies, A closing along +axis towards B");
  }
  for (size_t j = 0; j < 2; ++j)
    gripper.jaws[j] = BodyNamed(ctx, jaws[j], Index(map.Key("jaws"), j), scene);
  gripper.motion = std::make_shared<const KinematicMotion>(ReadMotion(
      ctx, map.Require("motion", "the frame's motion: {expressions | waypoints | velocity}"),
      map.Key("motion")));
  gripper.axis = ReadVector3(
      ctx, map.Require("axis", "[x, y, z]: the closing axis in the frame, from jaw A to jaw B"),
      map.Key("axis"), "a direction in the frame");
  if (!(gripper.axis.norm() >= kMinRotationAxisLength)) {
    map.FailAt("axis", "a non-zero axis [x, y, z] (it is normalized)");
  }
  gripper.force = ReadTimeFunction(
      ctx,
      map.Require("force", "the closing force on each jaw (N), a number or an expression of t"),
      map.Key("force"));
  return gripper;
}

}  // namespace ecpsim::engine::yaml
