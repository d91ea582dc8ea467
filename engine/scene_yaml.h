#pragma once
// Building a Scene from a YAML file (docs/scene_format.md) or from `ecpsim drop`'s options.

#include <string>
#include <vector>

#include "engine/scene.h"

namespace ecpsim::engine {

/// Reads the scene file `path` (format: docs/scene_format.md). `overrides` are "key=value"
/// strings (the CLI's --set) with dotted keys into the YAML tree, e.g. "h=0.005",
/// "bodies.0.mass=3", "solver.tolerance=1e-9"; each value is parsed as YAML ("[0, 0, 1]" is a
/// list) and applied before validation. Mesh paths are relative to the scene file's folder.
/// @throws InputError `path:line:col: key = value: expected ...` (line and column 1-based) for a
///         YAML syntax error, an unknown or duplicate key, a wrong type, a missing required key,
///         a non-finite number or one out of range, a missing mesh file, ...; an override whose
///         key does not fit the tree is named as `--set key=value`.
Scene LoadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// The options of `ecpsim drop`: one mesh dropped onto the ground plane z = 0.
struct DropOptions {
  std::string mesh;     // path of any mesh assimp reads
  double scale = 1;     // mesh units → m
  double height = 0.1;  // m, of the hull's lowest point above z = 0 at t = 0
  double tilt_deg = 0;  // initial rotation about the world x axis, degrees
  double spin = 0;      // rad/s, initial angular velocity about the world z axis
  double duration = 1;  // s
  double h = 0.01;      // s
  double mass = 0;      // kg; ≤ 0 means: density 1000 kg/m³ (water)
};

/// The drop scene: the mesh (its CM at x = y = 0, its hull computed with CGAL) above the ground
/// z = 0 with μ = 0.22, e = (1, 1, 0.1 m), gravity (0, 0, −9.8) m/s².
/// @throws InputError naming the option (e.g. `--height = -1`) for a non-finite or out-of-range
///         value, or the mesh's problem (missing, open, degenerate).
Scene MakeDropScene(const DropOptions& options);

}  // namespace ecpsim::engine
