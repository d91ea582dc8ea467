#pragma once
// The scene of `ecpsim drop`: one mesh dropped onto the ground plane z = 0, built from options.

#include <optional>
#include <string>

#include "engine/scene_io/loaded_scene.h"

namespace ecpsim::engine {

/// The options of `ecpsim drop`, each named in messages by its command-line spelling.
struct DropOptions {
  std::string mesh;                  // path of any mesh assimp reads
  std::optional<double> scale;       // --scale: mesh units → m (default 1)
  std::optional<std::string> units;  // --units mm|cm|m|in: the same as a unit name
  double height = 0.1;               // m, of the hull's lowest point above z = 0 at t = 0
  double tilt_deg = 0;               // initial rotation about the world x axis, degrees
  double spin = 0;                   // rad/s, initial angular velocity about the world z axis
  double duration = 1;               // s
  double h = 0.01;                   // s
  std::optional<double> mass;        // kg; default: density 1000 kg/m³ (water)
};

/// The drop scene: the mesh (its CM at x = y = 0, its hull computed with CGAL) above the ground
/// z = 0 with μ = 0.22, e = (1, 1, 0.1 m), gravity (0, 0, −9.8) m/s²; it passes ValidateScene,
/// whose error is reported as `ecpsim drop MESH: key = value: expected ...`. The output settings
/// are the defaults. A mesh outside [1 mm, 10 m] across adds a line naming --units / --scale to
/// LoadedScene::warnings.
/// @throws InputError naming the option (e.g. `--height = -1`) for a non-finite or out-of-range
///         value (scene_limits.h; --dt also against the step count), --scale and --units that
///         disagree, or the mesh's problem (missing, open, degenerate, implausibly sized).
LoadedScene MakeDropScene(const DropOptions& options);

}  // namespace ecpsim::engine
