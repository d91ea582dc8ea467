#pragma once
// The Python module's Scene and Simulation objects as the bindings hold them, shared by the
// binding files (ecpsim_module.cpp and the features bound in files of their own).

#include <memory>
#include <mutex>
#include <thread>

#include "engine/scene_io/loaded_scene.h"
#include "python/simulation.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace ecpsim::python {

// the Python Scene: the physics with its output settings and warnings; pybind11 holds it by a
// shared_ptr to non-const, and nothing here changes one once loaded
using SceneHandle = std::shared_ptr<engine::LoadedScene>;

// the renderer of one size, made on the thread that uses it (an OpenGL context is per thread)
struct RenderCache {
  std::unique_ptr<render::Renderer> renderer;
  std::unique_ptr<render::SceneFrameBuilder> frames;
  int width = 0, height = 0;
  std::thread::id thread;
};

// the Python Simulation
struct PySimulation {
  // the simulation shares the handle's ownership of the physics
  explicit PySimulation(SceneHandle scene_handle)
      : scene(std::move(scene_handle)),
        sim(std::shared_ptr<const engine::Scene>(scene, &scene->scene)) {}
  SceneHandle scene;
  Simulation sim;
  // one thread at a time in `sim` (stepping and rendering run without the GIL)
  std::mutex mutex;
  RenderCache render;
};

}  // namespace ecpsim::python
