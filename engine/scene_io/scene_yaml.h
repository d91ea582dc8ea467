#pragma once
// Building a Scene, with its output settings and warnings, from a YAML file
// (docs/scene_format.md).

#include <string>
#include <vector>

#include "engine/scene_io/loaded_scene.h"

namespace ecpsim::engine {

/// Reads the scene file `path` (format: docs/scene_format.md). `overrides` are "key=value"
/// strings (the CLI's --set) with dotted keys into the YAML tree, e.g. "h=0.005",
/// "bodies.0.mass=3", "solver.tolerance=1e-9"; each value is parsed as YAML ("[0, 0, 1]" is a
/// list) and applied before validation. Mesh paths are relative to the scene file's folder.
/// The scene and its `output` block then pass ValidateLoadedScene, its errors located in the
/// file. Meshes of implausible size (outside [1 mm, 10 m] across: wrong units?) add a line to
/// LoadedScene::warnings.
/// @throws InputError `path:line:col: key = value: expected ...` (line and column 1-based) for a
///         YAML syntax error, an unknown or duplicate key, a wrong type, a missing required key,
///         a non-finite number or one out of range (scene_limits.h), a string with a NUL, a
///         missing mesh file or any problem of the mesh, a scene ValidateScene rejects (too many
///         steps, an initial overlap with an obstacle, ...); an override whose key does not fit
///         the tree is named as `--set key=value`.
LoadedScene LoadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// As LoadScene, for a scene given as YAML text that no file holds (the Python module's dicts,
/// written as flow YAML): `source` names it in messages, which give the key path instead of a
/// line:col of a text the user never saw, and mesh paths are relative to `folder`.
/// @throws InputError `source: key = value: expected ...` as LoadScene.
LoadedScene LoadSceneText(const std::string& text, const std::string& source,
                          const std::string& folder,
                          const std::vector<std::string>& overrides = {});

}  // namespace ecpsim::engine
