#include "tests/engine/turned_deviation.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/errors.h"
#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/step_workspace.h"
#include "engine/time_step.h"
#include "tests/engine/turned_scene.h"

namespace ecpsim::engine::testing {
namespace {

// m: the farthest mesh vertex from the CM (the body frame's origin)
double BodyRadius(const Body& body) {
  double radius = 0;
  for (const Eigen::Vector3d& v : body.mesh.vertices) radius = std::max(radius, v.norm());
  return radius;
}

}  // namespace

TurnedDeviation MeasureTurnedDeviation(const Scene& scene, double angle, int steps) {
  const Scene turned = TurnedAboutZ(scene, angle);
  const TurnAboutZ back = TurnAboutZ(angle).Inverse();
  std::vector<double> radii;
  for (const Body& body : scene.bodies) radii.push_back(BodyRadius(body));
  State a = InitialState(scene), b = InitialState(turned);
  // one workspace per run: a workspace keeps nothing that changes results, but two keep the
  // runs as independent as two processes
  StepWorkspace workspace_a, workspace_b;
  TurnedDeviation deviation;
  for (int k = 0; k < steps; ++k) {
    Step(scene, a, workspace_a);
    Step(turned, b, workspace_b);
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
      const BodyState& x = a.bodies[i];
      const BodyState& y = b.bodies[i];
      const double position = (x.p_WB - back(y.p_WB)).norm();
      // the turn between the two orientations, shortest arc (QuaternionLog takes either sign)
      const double turn = QuaternionLog(x.Q_WB.conjugate() * back(y.Q_WB)).norm();
      if (position > deviation.position) {
        deviation.position = position;
        deviation.body = scene.bodies[i].name;
        deviation.time = a.t;
      }
      deviation.angle = std::max(deviation.angle, turn);
      deviation.surface = std::max(deviation.surface, turn * radii[i]);
    }
    deviation.steps = k + 1;
  }
  return deviation;
}

bool IsMultiBody(const Scene& scene) { return scene.bodies.size() > 1 || !scene.grippers.empty(); }

int RotationCheckSteps(const Scene& scene) {
  return static_cast<int>(std::lround(scene.duration / scene.h));
}

std::vector<std::string> MultiBodyScenes(const std::string& scenes_dir) {
  std::vector<std::string> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(scenes_dir)) {
    if (entry.path().extension() != ".yaml") continue;
    if (IsMultiBody(LoadScene(entry.path().string()).scene)) {
      scenes.push_back(entry.path().filename().string());
    }
  }
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

}  // namespace ecpsim::engine::testing
