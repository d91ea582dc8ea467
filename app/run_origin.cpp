#include "app/run_origin.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "app/version.h"
#include "common/errors.h"
#include "common/fnv1a.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// the path as an absolute, normalised one; symbolic links stay (a scene's meshes are found
// relative to the scene file's own folder)
std::string Absolute(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

}  // namespace

json RunArguments(const std::string& scene, const std::vector<std::string>& overrides, bool frames,
                  bool video) {
  return {{"command", "run"},
          {"scene", Absolute(scene)},
          {"overrides", overrides},
          {"frames", frames},
          {"video", video}};
}

namespace {

// an optional option as JSON: null when it was not given
template <typename T>
json Optional(const std::optional<T>& value) {
  return value ? json(*value) : json(nullptr);
}

template <typename T>
std::optional<T> ReadOptional(const json& node) {
  return node.is_null() ? std::nullopt : std::optional<T>(node.get<T>());
}

}  // namespace

json DropArguments(const engine::DropOptions& options, bool frames, bool video) {
  return {{"command", "drop"},
          {"mesh", Absolute(options.mesh)},
          {"scale", Optional(options.scale)},
          {"units", Optional(options.units)},
          {"height", options.height},
          {"tilt_deg", options.tilt_deg},
          {"spin", options.spin},
          {"duration", options.duration},
          {"h", options.h},
          {"mass", Optional(options.mass)},
          {"frames", frames},
          {"video", video}};
}

std::string CommandLine(const json& arguments) {
  std::string line = "ecpsim " + arguments.value("command", std::string("?"));
  if (arguments.value("command", "") == "run") {
    line += " " + arguments.at("scene").get<std::string>();
    for (const json& o : arguments.at("overrides")) line += " --set " + o.get<std::string>();
  } else {
    line += fmt::format(" {} --height {} --tilt {} --spin {} --duration {} --dt {}",
                        arguments.at("mesh").get<std::string>(), arguments.at("height").dump(),
                        arguments.at("tilt_deg").dump(), arguments.at("spin").dump(),
                        arguments.at("duration").dump(), arguments.at("h").dump());
    if (!arguments.at("scale").is_null()) line += " --scale " + arguments.at("scale").dump();
    if (!arguments.at("units").is_null()) {
      line += " --units " + arguments.at("units").get<std::string>();
    }
    if (!arguments.at("mass").is_null()) line += " --mass " + arguments.at("mass").dump();
  }
  if (arguments.value("frames", false)) line += " --frames";
  if (arguments.value("video", false)) line += " --video";
  return line;
}

engine::LoadedScene SceneOf(const json& arguments) {
  try {
    arguments.at("frames").get<bool>();
    arguments.at("video").get<bool>();
    const std::string command = arguments.at("command").get<std::string>();
    if (command == "run") {
      return engine::LoadScene(arguments.at("scene").get<std::string>(),
                               arguments.at("overrides").get<std::vector<std::string>>());
    }
    if (command == "drop") {
      engine::DropOptions options;
      options.mesh = arguments.at("mesh").get<std::string>();
      options.scale = ReadOptional<double>(arguments.at("scale"));
      options.units = ReadOptional<std::string>(arguments.at("units"));
      options.height = arguments.at("height").get<double>();
      options.tilt_deg = arguments.at("tilt_deg").get<double>();
      options.spin = arguments.at("spin").get<double>();
      options.duration = arguments.at("duration").get<double>();
      options.h = arguments.at("h").get<double>();
      options.mass = ReadOptional<double>(arguments.at("mass"));
      return engine::MakeDropScene(options);
    }
  } catch (const json::exception& e) {
    throw InputError(fmt::format("arguments {}: {}", arguments.dump(), e.what()));
  }
  throw InputError(fmt::format("arguments {}: expected those of `ecpsim run` or `ecpsim drop`",
                               arguments.dump()));
}

json RunOrigin(const json& arguments, const engine::Scene& scene) {
  Fnv1a inputs;
  if (arguments.value("command", "") == "run") {
    std::ifstream file(arguments.at("scene").get<std::string>(), std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(file), {}};
    inputs.Add(bytes.data(), bytes.size());
  }
  for (const engine::Body& body : scene.bodies) {
    for (const Eigen::Vector3d& v : body.mesh.vertices) inputs.Add(v.data(), sizeof(double) * 3);
    for (const Eigen::Vector3i& t : body.mesh.triangles) inputs.Add(t.data(), sizeof(int) * 3);
  }
  return {{"arguments", arguments}, {"inputs", inputs.Hex()}, {"ecpsim", kVersionText}};
}

void RequireSameOrigin(const json& stored, const json& now, const std::string& checkpoint_path) {
  if (stored.value("ecpsim", "") != now.at("ecpsim")) {
    throw InputError(
        fmt::format("{}: written by {}, this is {}; resume with the same build, or "
                    "start the run again",
                    checkpoint_path, stored.value("ecpsim", "an unknown version"),
                    now.at("ecpsim").get<std::string>()));
  }
  if (stored.value("inputs", "") != now.at("inputs")) {
    const json& arguments = now.at("arguments");
    const std::string input =
        arguments.value("command", "") == "run"
            ? "the scene file " + arguments.at("scene").get<std::string>() + " or a mesh it names"
            : "the mesh " + arguments.at("mesh").get<std::string>();
    throw InputError(fmt::format(
        "{}: {} has changed since the run began (fingerprint {}, now "
        "{}); a resumed run needs the same inputs: restore them, or "
        "start the run again",
        checkpoint_path, input, stored.value("inputs", "?"), now.at("inputs").get<std::string>()));
  }
}

}  // namespace ecpsim::app
