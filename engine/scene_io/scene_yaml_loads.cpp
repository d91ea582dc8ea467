// Loads and impulses of the scene format: forces and torques as expressions of t, and impulses.

#include <cmath>

#include "engine/scene_io/scene_yaml_reader.h"

namespace ecpsim::engine::yaml {
namespace {

// a constant force/torque component whose end is not given
constexpr double kForever = 1e300;  // s, as Load::end's default

// a body by name, or by index into `bodies`
int ReadBodyReference(const Context& ctx, const MapNode& map, const std::vector<Body>& bodies) {
  if (!map.Has("body")) {
    if (bodies.size() == 1) return 0;
    map.FailAt("body", "a body name (required: the scene has several)");
  }
  const YAML::Node node = map.Get("body");
  std::string names;
  for (const Body& b : bodies) names += (names.empty() ? "" : ", ") + b.name;
  const std::string expected =
      fmt::format("a body name ({}) or index 0..{}", names, bodies.size() - 1);
  if (!node.IsScalar()) Fail(ctx, node, map.Key("body"), expected);
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == node.Scalar()) return static_cast<int>(i);
  }
  int index = -1;
  if (!YAML::convert<int>::decode(node, index) || index < 0 ||
      index >= static_cast<int>(bodies.size())) {
    Fail(ctx, node, map.Key("body"), expected);
  }
  return index;
}

// `start` and `end` (ordering: ValidateScene)
void ReadWindow(const Context& ctx, const MapNode& map, double& start, double& end) {
  start = map.Has("start")
              ? ReadNumber(ctx, map.Get("start"), map.Key("start"), "a finite start time (s)")
              : 0.0;
  end = map.Has("end")
            ? ReadNumber(ctx, map.Get("end"), map.Key("end"), "a finite end time (s) > start")
            : kForever;
}

// `at`: a point in the mesh file's frame, returned in the body (CM) frame
Eigen::Vector3d ReadPoint(const Context& ctx, const MapNode& map, const BodyExtras& extras) {
  return ReadVector3(ctx, map.Get("at"), map.Key("at"), "m, mesh frame") - extras.center_of_mass;
}

}  // namespace

TimeFunction ReadTimeFunction(const Context& ctx, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) {
    Fail(ctx, node, key, "a number or an expression of t in quotes");
  }
  double value = 0;
  if (YAML::convert<double>::decode(node, value)) {
    return TimeFunction(ReadNumber(ctx, node, key, "a finite number or an expression of t"));
  }
  const std::string expression =
      ReadString(ctx, node, key, "a number or an expression of t in quotes");
  return TimeFunction(expression, fmt::format("{}: {}", Where(ctx, node, key), key));
}

Load ReadLoad(const Context& ctx, const YAML::Node& node, const std::string& key,
              const std::vector<Body>& bodies, const std::vector<BodyExtras>& extras) {
  const MapNode map(ctx, node, key, {"body", "force", "torque", "at", "start", "end"});
  Load load;
  load.body = ReadBodyReference(ctx, map, bodies);
  if (map.Has("force") == map.Has("torque")) {
    Fail(ctx, node, key, "exactly one of `force` [N] or `torque` [N·m] (world frame)");
  }
  load.kind = map.Has("force") ? Load::Kind::kForce : Load::Kind::kTorque;
  const std::string name = map.Has("force") ? "force" : "torque";
  const YAML::Node components = map.Get(name);
  if (!components.IsSequence() || components.size() != 3) {
    Fail(ctx, components, map.Key(name),
         "a list of 3 components [x, y, z] (world frame), each a number or an expression of t");
  }
  load.x = ReadTimeFunction(ctx, components[0], Index(map.Key(name), 0));
  load.y = ReadTimeFunction(ctx, components[1], Index(map.Key(name), 1));
  load.z = ReadTimeFunction(ctx, components[2], Index(map.Key(name), 2));
  if (map.Has("at")) {
    if (load.kind == Load::Kind::kTorque) {
      map.FailAt("at", "`at` only with a force (a torque has no point)");
    }
    load.at_point = true;
    load.point_B = ReadPoint(ctx, map, extras[load.body]);
  }
  ReadWindow(ctx, map, load.start, load.end);
  return load;
}

Impulse ReadImpulse(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const std::vector<Body>& bodies, const std::vector<BodyExtras>& extras) {
  const MapNode map(ctx, node, key, {"body", "time", "linear", "angular", "at"});
  Impulse impulse;
  impulse.body = ReadBodyReference(ctx, map, bodies);
  impulse.time = ReadNumber(ctx, map.Require("time", "a time >= 0 s"), map.Key("time"),
                            "a finite time >= 0 s");
  if (!map.Has("linear") && !map.Has("angular")) {
    map.FailAt("linear", "`linear` [N·s] and/or `angular` [N·m·s] (world frame)");
  }
  if (map.Has("linear")) {
    impulse.linear = ReadVector3(ctx, map.Get("linear"), map.Key("linear"), "N·s, world frame");
  }
  if (map.Has("angular")) {
    impulse.angular = ReadVector3(ctx, map.Get("angular"), map.Key("angular"),
                                  "N·m·s, world frame, about the CM");
  }
  if (map.Has("at")) {
    if (!map.Has("linear")) {
      map.FailAt("at", "`at` only together with `linear`");
    }
    impulse.at_point = true;
    impulse.point_B = ReadPoint(ctx, map, extras[impulse.body]);
  }
  return impulse;
}

}  // namespace ecpsim::engine::yaml
