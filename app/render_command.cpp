// `ecpsim render SCENE --time T -o frame.png`: one frame of a scene, simulated up to T.

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/commands.h"
#include "app/frame_recorder.h"
#include "engine/scene_yaml.h"
#include "engine/time_step.h"
#include "common/errors.h"
#include "render/png_writer.h"

namespace ecpsim::app {
namespace {

struct RenderOptions {
  std::string scene;
  std::string out;
  double time = 0;
  std::vector<std::string> overrides;
  std::optional<int> width, height;
};

}  // namespace

void AddRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* render = app.add_subcommand(
      "render", "Render one frame of a scene at time T (simulating up to T) to a PNG; the output "
                "is deterministic on a given machine, for image-based regression tests");
  render->add_option("scene", options->scene, "scene file (YAML)")->required();
  render->add_option("-o,--out", options->out, "PNG file to write")->required();
  render->add_option("--time", options->time, "simulated time of the frame, s (default 0)")
      ->check(CLI::NonNegativeNumber);
  render->add_option("--set", options->overrides, "override a scene value, key=value");
  render->add_option("--width", options->width, "pixels (default: the scene's, else 1280)")
      ->check(CLI::Range(16, 8192));
  render->add_option("--height", options->height, "pixels (default: the scene's, else 720)")
      ->check(CLI::Range(16, 8192));
  render->callback([options] {
    if (!std::isfinite(options->time)) {
      throw InputError(fmt::format("--time = {}: expected a finite time >= 0 s", options->time));
    }
    std::vector<std::string> overrides = options->overrides;
    if (options->width) overrides.push_back(fmt::format("output.width={}", *options->width));
    if (options->height) overrides.push_back(fmt::format("output.height={}", *options->height));
    const engine::Scene scene = engine::LoadScene(options->scene, overrides);

    // the state nearest to T
    engine::State state = engine::InitialState(scene);
    int iterations = 0;
    while (state.t + scene.h / 2 <= options->time) iterations = engine::Step(scene, state).iterations;

    render::Renderer renderer(RenderSettingsFor(scene));
    render::FrameInput frame = render::SceneFrameBuilder(scene).Build(state, iterations);
    ApplyCamera(scene, frame);
    render::WritePng(options->out, renderer.Render(frame));
    std::printf("t = %.6g s: wrote %s\n", state.t, options->out.c_str());
  });
}

}  // namespace ecpsim::app
