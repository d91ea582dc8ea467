// `ecpsim render SCENE --time T -o frame.png`: one frame of a scene, simulated up to T.

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/commands.h"
#include "app/frame_recorder.h"
#include "app/option_checks.h"
#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"
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
      "render",
      "Render one frame of a scene at time T (simulating up to T) to a PNG; the output "
      "is deterministic on a given machine, for image-based regression tests");
  render->add_option("scene", options->scene, "scene file (YAML)")->required();
  render->add_option("-o,--out", options->out, "PNG file to write")->required();
  render
      ->add_option("--time", options->time,
                   "simulated time of the frame, s, within the scene's duration (default 0)")
      ->check(FiniteNumber("--time"));
  render->add_option("--set", options->overrides, "override a scene value, key=value");
  render->add_option("--width", options->width, "pixels (default: the scene's, else 1280)")
      ->check(IntegerInRange("--width", engine::kMinFramePixels, engine::kMaxFramePixels));
  render->add_option("--height", options->height, "pixels (default: the scene's, else 720)")
      ->check(IntegerInRange("--height", engine::kMinFramePixels, engine::kMaxFramePixels));
  render->callback([options] {
    std::vector<std::string> overrides = options->overrides;
    if (options->width) overrides.push_back(fmt::format("output.width={}", *options->width));
    if (options->height) overrides.push_back(fmt::format("output.height={}", *options->height));
    const engine::LoadedScene loaded = engine::LoadScene(options->scene, overrides);
    PrintWarnings(loaded);
    const engine::Scene& scene = loaded.scene;
    // the step count of a run bounds the stepping below
    if (!(options->time >= 0 && options->time <= scene.duration)) {
      throw InputError(
          fmt::format("--time = {}: expected a time in [0, {}] s, the scene's "
                      "duration",
                      options->time, scene.duration));
    }

    // the state nearest to T
    engine::State state = engine::InitialState(scene);
    engine::StepReport report;
    engine::StepWorkspace workspace;
    while (state.t + scene.h / 2 <= options->time) report = engine::Step(scene, state, workspace);

    render::Renderer renderer(RenderSettingsFor(loaded.output));
    render::FrameInput frame =
        render::SceneFrameBuilder(scene).Build(state, report.iterations, report.models);
    ApplyCamera(loaded, frame);
    render::WritePng(options->out, renderer.Render(frame));
    std::printf("t = %.6g s: wrote %s\n", state.t, options->out.c_str());
  });
}

}  // namespace ecpsim::app
