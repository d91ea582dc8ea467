// Measures how far each shipped multi-body scene turned about z moves from its turned motion:
// `ecpsim_rotation_check SCENES_DIR [SCENE.yaml ...]` prints, per scene and turn (90°, 37°), the
// largest CM deviation (m), the largest orientation difference (rad) and the CPU time of the two
// runs (tests/engine/turned_deviation.h). Exit 1 if a run fails.

#include <cmath>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/scene_io/scene_yaml.h"
#include "tests/engine/turned_deviation.h"

namespace {

// the turns: a quarter turn (exact: coordinates permuted) and one that rounds every
// product and aligns no face with a world axis
struct Turn {
  const char* name;
  double angle;  // rad
};
constexpr Turn kTurns[] = {{"90", M_PI / 2}, {"37", 37 * M_PI / 180}};

}  // namespace

int main(int argc, char** argv) {
  using namespace ecpsim::engine;
  if (argc < 2) {
    fmt::print(stderr, "usage: ecpsim_rotation_check SCENES_DIR [SCENE.yaml ...]\n");
    return 2;
  }
  const std::string dir = argv[1];
  try {
    std::vector<std::string> scenes(argv + 2, argv + argc);
    if (scenes.empty()) scenes = testing::MultiBodyScenes(dir);
    fmt::print(
        "# each scene and its copy turned about z stepped side by side under the scene's model;\n"
        "# the largest over bodies and steps of |CM − R⁻¹ CM'| (m) and of the turn from Q to\n"
        "# R⁻¹ Q' (rad); cpu: both runs (tests/engine/turned_deviation.h)\n");
    fmt::print("{:<16} {:>5} {:>6} {:>7} {:>12} {:>12}  {:<22} {:>7}\n", "scene", "turn", "steps",
               "t (s)", "cm (m)", "angle (rad)", "largest at", "cpu (s)");
    bool failed = false;
    for (const std::string& name : scenes) {
      const Scene scene = LoadScene(dir + "/" + name).scene;
      const int steps = testing::RotationCheckSteps(scene);
      for (const Turn& turn : kTurns) {
        const std::clock_t start = std::clock();
        try {
          const testing::TurnedDeviation d =
              testing::MeasureTurnedDeviation(scene, turn.angle, steps);
          const double cpu = double(std::clock() - start) / CLOCKS_PER_SEC;
          fmt::print("{:<16} {:>4}° {:>6} {:>7.3f} {:>12.3e} {:>12.3e}  {:<22} {:>7.2f}\n", name,
                     turn.name, d.steps, d.steps * scene.h, d.position, d.angle,
                     fmt::format("{} at {:.2f} s", d.body, d.time), cpu);
        } catch (const std::exception& e) {
          failed = true;
          fmt::print("{:<16} {:>4}° failed: {}\n", name, turn.name, e.what());
        }
        std::fflush(stdout);
      }
    }
    return failed ? 1 : 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "ecpsim_rotation_check: {}\n", e.what());
    return 1;
  }
}
