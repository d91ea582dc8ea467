#pragma once
// What identifies a run for `ecpsim run --resume DIR`: the command and its arguments as first
// given (paths made absolute), a fingerprint of the input files they name, and the ecpsim build.
// It is kept in checkpoint.json (Checkpoint::origin), and a resume must reproduce it exactly:
// the same arguments, the same scene and mesh files, the same ecpsim.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/scene.h"
#include "engine/scene_io/drop_scene.h"
#include "engine/scene_io/scene_yaml.h"

namespace ecpsim::app {

/// The arguments of `ecpsim run SCENE [overrides…] [--frames] [--video]`: the scene's absolute
/// path, the overrides in order (the --set values, then --model, --fps, … as `key=value`), and
/// whether PNG frames (`frames`) and a video (`video`) were asked for, each as given: a video
/// alone is rendered without PNG frames, so a resume must know which it was.
nlohmann::json RunArguments(const std::string& scene, const std::vector<std::string>& overrides,
                            bool frames, bool video);

/// The arguments of `ecpsim drop MESH …`: every DropOptions field (the mesh's path absolute),
/// frames and video as in RunArguments.
nlohmann::json DropArguments(const engine::DropOptions& options, bool frames, bool video);

/// `arguments` as a command line, for messages: `ecpsim run /abs/scene.yaml --set h=0.001 …`.
std::string CommandLine(const nlohmann::json& arguments);

/// The scene that `arguments` (from RunArguments or DropArguments) describe, loaded again.
/// @throws InputError as engine::LoadScene and engine::MakeDropScene do, or for arguments that
///         are neither (or lack the frames and video flags).
engine::LoadedScene SceneOf(const nlohmann::json& arguments);

/// The origin of a run: {"arguments": `arguments`, "inputs": a 64-bit FNV-1a fingerprint (hex)
/// of the scene file's bytes and of every body's mesh as loaded, "ecpsim": the version text}.
/// The fingerprint tells an edited input from the same one; it is no security measure.
nlohmann::json RunOrigin(const nlohmann::json& arguments, const engine::Scene& scene);

/// Checks that the origin of the run to resume, rebuilt `now` from its stored arguments, is the
/// `stored` one.
/// @throws InputError naming `checkpoint_path`, what changed (the scene file or a mesh since the
///         run began, or the ecpsim build) and that a new run must start from t = 0.
void RequireSameOrigin(const nlohmann::json& stored, const nlohmann::json& now,
                       const std::string& checkpoint_path);

}  // namespace ecpsim::app
