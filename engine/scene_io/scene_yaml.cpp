#include "engine/scene_io/scene_yaml.h"

#include <filesystem>

#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/scene_io/scene_yaml_reader.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;
using yaml::BodyNamed;
using yaml::Context;
using yaml::Fail;
using yaml::Index;
using yaml::MapNode;

SolverSettings ReadSolver(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key,
                    {"tolerance", "max_iterations", "window_rings", "use_window", "selection", "sleep"});
  SolverSettings solver;
  if (map.Has("tolerance")) {
    solver.tolerance = yaml::ReadNumber(ctx, map.Get("tolerance"), map.Key("tolerance"),
                                        "a residual tolerance > 0");
  }
  if (map.Has("max_iterations")) {
    solver.max_iterations =
        yaml::ReadInt(ctx, map.Get("max_iterations"), map.Key("max_iterations"), "an integer >= 1");
  }
  if (map.Has("window_rings")) {
    solver.window_rings =
        yaml::ReadInt(ctx, map.Get("window_rings"), map.Key("window_rings"), "an integer >= 0");
  }
  if (map.Has("use_window")) {
    solver.use_window = yaml::ReadBool(ctx, map.Get("use_window"), map.Key("use_window"));
  }
  if (map.Has("sleep")) solver.sleep = yaml::ReadBool(ctx, map.Get("sleep"), map.Key("sleep"));
  if (map.Has("selection")) {
    const YAML::Node value = map.Get("selection");
    const auto named = [&](Selection s) {
      return value.IsScalar() && value.Scalar() == SelectionName(s);
    };
    if (named(Selection::kCreep)) {
      solver.selection = Selection::kCreep;
    } else if (named(Selection::kLeastEnergy)) {
      solver.selection = Selection::kLeastEnergy;
    } else {
      Fail(ctx, value, map.Key("selection"), "one of creep, least_energy");
    }
  }
  return solver;
}

OutputSettings ReadOutput(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key, {"every", "fps", "width", "height", "camera"});
  OutputSettings output;
  if (map.Has("every")) {
    output.every = yaml::ReadInt(ctx, map.Get("every"), map.Key("every"),
                                 "an integer >= 1 (write every N-th step)");
  }
  if (map.Has("fps")) {
    output.fps = yaml::ReadNumber(ctx, map.Get("fps"), map.Key("fps"),
                                  "a finite frame rate > 0 frames per simulated second");
  }
  if (map.Has("width")) {
    output.width =
        yaml::ReadInt(ctx, map.Get("width"), map.Key("width"), "an integer width >= 16 pixels");
  }
  if (map.Has("height")) {
    output.height =
        yaml::ReadInt(ctx, map.Get("height"), map.Key("height"), "an integer height >= 16 pixels");
  }
  if (map.Has("camera")) {
    const MapNode camera(ctx, map.Get("camera"), map.Key("camera"), {"position", "target", "fov"});
    output.camera_fixed = true;
    output.camera_position = yaml::ReadVector3(
        ctx, camera.Require("position", "[x, y, z] m, world"), camera.Key("position"), "m, world");
    if (camera.Has("target")) {
      output.camera_target =
          yaml::ReadVector3(ctx, camera.Get("target"), camera.Key("target"), "m, world");
    }
    if (camera.Has("fov")) {
      output.camera_fov_deg = yaml::ReadNumber(ctx, camera.Get("fov"), camera.Key("fov"),
                                               "a vertical field of view in (0, 180) degrees");
    }
  }
  return output;
}

// "obstacles[i]..." of the Scene is "ground..." or "obstacles[i - 1]..." in a file with `ground`
std::string FileKey(const std::string& key, bool has_ground) {
  const std::string prefix = "obstacles[";
  if (!has_ground || key.rfind(prefix, 0) != 0) return key;
  const size_t close = key.find(']');
  const int index = std::stoi(key.substr(prefix.size(), close - prefix.size()));
  const std::string rest = key.substr(close + 1);
  return index == 0 ? "ground" + rest : fmt::format("obstacles[{}]{}", index - 1, rest);
}

// a ValidateScene error at the first of its keys that a --set gave, else the first the file
// has, as file:line:col
InputError Locate(const Context& ctx, const YAML::Node& root, const SceneError& error) {
  const bool has_ground = static_cast<bool>(root["ground"]);
  std::vector<std::string> keys;
  for (const std::string& scene_key : error.keys()) {
    const std::string key = FileKey(scene_key, has_ground);
    const bool overridden =
        yaml::Where(ctx, YAML::Node(), key).find(": --set ") != std::string::npos;
    keys.insert(overridden ? keys.begin() : keys.end(), key);
  }
  for (const std::string& key : keys) {
    const YAML::Node node = yaml::FindNode(root, key);
    if (node.IsDefined()) {
      return InputError(fmt::format("{}: {} = {}: expected {}", yaml::Where(ctx, node, key), key,
                                    yaml::Show(node), error.expected()));
    }
  }
  return InputError(fmt::format("{}: {}", ctx.file, error.what()));
}

YAML::Node ReadFile(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    throw InputError(
        fmt::format("scene file {}: cannot open it; expected an existing YAML file", path));
  }
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError(fmt::format("{}:{}:{}: YAML syntax error: {}", path, e.mark.line + 1,
                                 e.mark.column + 1, yaml::Printable(e.msg)));
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("scene file {}: cannot read it: {}", path, e.msg));
  }
}

// the pair of bodies (i, j) with its settings from `pairs:` (none: PairFriction of the two)
struct PairSetting {
  bool exclude = false;
  Friction friction;
};

// every pair of bodies that can touch (not both kinematic, not excluded by `pairs:`) becomes a
// contact: F the dynamic body (the lower index when both are), G the other
void AddBodyPairs(const Context& ctx, const MapNode& map, Scene& scene) {
  const size_t n = scene.bodies.size();
  std::vector<std::vector<PairSetting>> settings(n, std::vector<PairSetting>(n));
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      settings[i][j].friction = PairFriction(scene.bodies[i].friction, scene.bodies[j].friction);
  if (map.Has("pairs")) {
    const YAML::Node list = map.Get("pairs");
    if (!list.IsSequence()) {
      Fail(ctx, list, "pairs",
           "a list of `- {bodies: [A, B], friction: {...}}` or `exclude: true`");
    }
    for (size_t k = 0; k < list.size(); ++k) {
      const std::string key = Index("pairs", k);
      const MapNode entry(ctx, list[k], key, {"bodies", "friction", "exclude"});
      const YAML::Node names = entry.Require("bodies", "[A, B]: the names of two bodies");
      if (!names.IsSequence() || names.size() != 2) {
        Fail(ctx, names, entry.Key("bodies"), "[A, B]: the names of two bodies");
      }
      const int a = BodyNamed(ctx, names[0], Index(entry.Key("bodies"), 0), scene);
      const int b = BodyNamed(ctx, names[1], Index(entry.Key("bodies"), 1), scene);
      if (a == b) Fail(ctx, names, entry.Key("bodies"), "two different bodies");
      PairSetting setting = settings[a][b];
      if (entry.Has("exclude")) {
        setting.exclude = yaml::ReadBool(ctx, entry.Get("exclude"), entry.Key("exclude"));
      }
      if (entry.Has("friction")) {
        setting.friction =
            yaml::ReadFriction(ctx, entry.Get("friction"), entry.Key("friction"), setting.friction);
      }
      settings[a][b] = settings[b][a] = setting;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      if (scene.bodies[i].IsKinematic() && scene.bodies[j].IsKinematic()) continue;
      if (settings[i][j].exclude) continue;
      AddBodyContacts(scene, static_cast<int>(i), static_cast<int>(j), settings[i][j].friction);
    }
  }
}

LoadedScene ReadScene(const Context& ctx, const YAML::Node& root) {
  const MapNode map(ctx, root, "",
                    {"gravity", "h", "duration", "ground", "obstacles", "bodies", "loads",
                     "impulses", "solver", "output", "model", "pairs", "grippers"});
  LoadedScene loaded;
  Scene& scene = loaded.scene;
  scene.source = ctx.file;
  if (map.Has("model")) scene.model = yaml::ReadModel(ctx, map.Get("model"), "model");
  if (map.Has("gravity")) {
    scene.gravity = yaml::ReadVector3(ctx, map.Get("gravity"), "gravity", "m/s², world frame");
  }
  scene.duration = yaml::ReadPositive(ctx, map.Require("duration", "a duration > 0 s"), "duration",
                                      kTimeRange, "a finite duration > 0 s");
  if (map.Has("h")) {
    scene.h = yaml::ReadPositive(ctx, map.Get("h"), "h", kTimeRange, "a finite time step > 0 s");
  }
  // h against duration here, where it is known whether h is the default
  if (scene.h > scene.duration) {
    if (map.Has("h")) {
      Fail(ctx, map.Get("h"), "h", fmt::format("a time step <= duration = {} s", scene.duration));
    }
    Fail(ctx, map.Get("duration"), "duration",
         fmt::format("a duration >= the default time step h = {} s", scene.h));
  }

  // obstacles: the ground first, then the list
  if (map.Has("ground")) {
    scene.obstacles.push_back(yaml::ReadGround(ctx, map.Get("ground"), "ground"));
  }
  if (map.Has("obstacles")) {
    const YAML::Node list = map.Get("obstacles");
    if (!list.IsSequence()) {
      Fail(ctx, list, "obstacles", "a list of obstacles (`- plane: ...` or `- box: ...`)");
    }
    for (size_t i = 0; i < list.size(); ++i) {
      scene.obstacles.push_back(
          yaml::ReadObstacle(ctx, list[i], Index("obstacles", i), fmt::format("obstacle{}", i)));
    }
  }

  // bodies
  const YAML::Node bodies = map.Require("bodies", "a list of at least one body");
  if (!bodies.IsSequence() || bodies.size() == 0) {
    Fail(ctx, bodies, "bodies", "a list of at least one body");
  }
  std::vector<yaml::BodyExtras> extras(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    scene.bodies.push_back(yaml::ReadBody(ctx, bodies[i], Index("bodies", i),
                                          fmt::format("body{}", i), extras[i], loaded.warnings));
  }

  // one contact per (dynamic body, obstacle), with the obstacle's friction under the body's
  // overrides; a kinematic body is never pushed, so it has none
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    // the body's own friction, for its contacts with bodies: its overrides on the ground's
    const Friction base = scene.obstacles.empty() ? Friction{} : scene.obstacles[0].friction;
    scene.bodies[b].friction = extras[b].friction ? yaml::ReadFriction(ctx, *extras[b].friction,
                                                                       extras[b].friction_key, base)
                                                  : base;
    if (scene.bodies[b].IsKinematic()) continue;
    for (size_t o = 0; o < scene.obstacles.size(); ++o) {
      Friction friction = scene.obstacles[o].friction;
      if (extras[b].friction) {
        friction = yaml::ReadFriction(ctx, *extras[b].friction, extras[b].friction_key, friction);
      }
      AddObstacleContacts(scene, static_cast<int>(b), static_cast<int>(o), friction);
    }
  }
  AddBodyPairs(ctx, map, scene);

  if (map.Has("loads")) {
    const YAML::Node list = map.Get("loads");
    if (!list.IsSequence()) Fail(ctx, list, "loads", "a list of loads");
    for (size_t i = 0; i < list.size(); ++i) {
      scene.loads.push_back(yaml::ReadLoad(ctx, list[i], Index("loads", i), scene.bodies, extras));
    }
  }
  if (map.Has("grippers")) {
    const YAML::Node list = map.Get("grippers");
    if (!list.IsSequence()) {
      Fail(ctx, list, "grippers", "a list of `- {name, jaws: [A, B], motion, axis, force}`");
    }
    for (size_t i = 0; i < list.size(); ++i)
      AddGripper(scene, yaml::ReadGripper(ctx, list[i], Index("grippers", i), scene));
  }
  if (map.Has("impulses")) {
    const YAML::Node list = map.Get("impulses");
    if (!list.IsSequence()) Fail(ctx, list, "impulses", "a list of impulses");
    for (size_t i = 0; i < list.size(); ++i) {
      scene.impulses.push_back(
          yaml::ReadImpulse(ctx, list[i], Index("impulses", i), scene.bodies, extras));
    }
  }
  if (map.Has("solver")) scene.solver = ReadSolver(ctx, map.Get("solver"), "solver");
  if (map.Has("output")) loaded.output = ReadOutput(ctx, map.Get("output"), "output");
  return loaded;
}

// LoadScene's work on a parsed tree: the overrides applied, read, validated
LoadedScene LoadTree(Context ctx, YAML::Node root, const std::vector<std::string>& overrides) {
  if (root.IsNull() && overrides.empty()) {
    throw InputError(
        fmt::format("{}{}: the scene is empty; expected a mapping with at least `duration` and "
                    "`bodies`",
                    ctx.file, ctx.has_lines ? ":1:1" : ""));
  }
  std::vector<yaml::Override> applied;
  for (const std::string& o : overrides) yaml::ApplyOverride(ctx, root, o, applied);
  ctx.overrides = applied;

  LoadedScene loaded = ReadScene(ctx, root);
  try {
    ValidateLoadedScene(loaded);
  } catch (const SceneError& e) {
    throw Locate(ctx, root, e);
  }
  IndexContacts(loaded.scene);
  return loaded;
}

}  // namespace

LoadedScene LoadScene(const std::string& path, const std::vector<std::string>& overrides) {
  Context ctx;
  ctx.file = path;
  ctx.folder = fs::path(path).parent_path();
  return LoadTree(std::move(ctx), ReadFile(path), overrides);
}

LoadedScene LoadSceneText(const std::string& text, const std::string& source,
                          const std::string& folder, const std::vector<std::string>& overrides) {
  Context ctx;
  ctx.file = source;
  ctx.folder = folder;
  ctx.has_lines = false;
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: not a YAML tree: {}", source, yaml::Printable(e.msg)));
  }
  return LoadTree(std::move(ctx), std::move(root), overrides);
}

}  // namespace ecpsim::engine
