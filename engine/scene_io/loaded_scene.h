#pragma once
// What a scene's source gives its caller: the physics (a validated Scene, all the engine sees),
// what `ecpsim run` writes (OutputSettings) and the notes found while loading (warnings).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/scene.h"

namespace ecpsim::engine {

/// pixels, frame width and height (`output.width`, `--width`): as the renderer's buffers allow
inline constexpr int kMinFramePixels = 16;
inline constexpr int kMaxFramePixels = 8192;

/// What `ecpsim run` writes: the scene file's `output` block (docs/scene_format.md).
struct OutputSettings {
  int every = 1;  // write every N-th step to trajectory.csv (plus the first and last state)
  // frames (`ecpsim run --frames/--video`, `ecpsim render`)
  double fps = 30;            // frames per simulated second, independent of h
  int width = 1280;           // pixels
  int height = 720;           // pixels
  bool camera_fixed = false;  // false: automatic framing that follows the bodies
  Eigen::Vector3d camera_position = Eigen::Vector3d(1.2, -1.8, 1.1);  // m, world
  Eigen::Vector3d camera_target = Eigen::Vector3d::Zero();            // m, world
  double camera_fov_deg = 35;  // vertical field of view, degrees
};

/// A scene as LoadScene, MakeDropScene and the Python module's make_scene return it.
struct LoadedScene {
  Scene scene;            // passed ValidateScene; the engine steps it
  OutputSettings output;  // passed ValidateLoadedScene with `scene` (defaults: no `output` block)
  // one-line notes found while loading that are no errors (a mesh of implausible size: wrong
  // units?), for the caller to show; the loaders never print
  std::vector<std::string> warnings;
};

}  // namespace ecpsim::engine
