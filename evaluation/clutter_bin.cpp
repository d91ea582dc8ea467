#include "evaluation/clutter_bin.h"

#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_validation.h"
#include "evaluation/scenario.h"
#include "evaluation/seeded_random.h"
#include "geometry/convex_shape.h"

namespace ecpsim::evaluation {

using Eigen::Vector3d;

namespace {

// m: a mean box's edge, whose square face's mean radius is the friction's torsion e_r
constexpr double kMeanEdge = 0.5 * (kClutterEdgeMin + kClutterEdgeMax);

}  // namespace

engine::Scene ClutterBinScene(int boxes, std::uint64_t seed, double h) {
  ECPSIM_DEMAND(boxes >= 1 && boxes <= kMaxClutterBoxes && h > 0);
  const engine::Friction friction{kClutterMu, 1, 1, MeanRadiusOfRectangle(kMeanEdge, kMeanEdge)};
  // the sizes and the poses from separate streams: a box's size does not move the others' poses
  SeededRandom sizes(seed, 0), poses(seed, 1);
  constexpr int kPerLayer = kClutterPerRow * kClutterPerRow;
  const double first = -0.5 * (kClutterPerRow - 1) * kClutterPitch;
  std::vector<engine::Body> bodies;
  bodies.reserve(boxes);
  for (int i = 0; i < boxes; ++i) {
    Vector3d size;
    for (int axis = 0; axis < 3; ++axis)
      size[axis] = sizes.Uniform(kClutterEdgeMin, kClutterEdgeMax);
    engine::Body box =
        engine::MakeBoxBody(size, kClutterDensity * size.prod(), fmt::format("b{}", i));
    box.friction = friction;
    const int layer = i / kPerLayer, cell = i % kPerLayer;
    box.p0 =
        Vector3d(first + (cell % kClutterPerRow) * kClutterPitch + poses.Uniform(-kClutterJitter, kClutterJitter),
                 first + (cell / kClutterPerRow) * kClutterPitch + poses.Uniform(-kClutterJitter, kClutterJitter),
                 (layer + 1) * kClutterPitch);
    box.q0 = poses.Rotation();
    bodies.push_back(std::move(box));
  }
  engine::Scene scene = engine::MakeGroundScene(std::move(bodies), h, friction);
  scene.source = fmt::format("clutter bin of {} boxes, seed {}", boxes, seed);
  scene.duration = 2 * kClutterSettleTime;
  const double half = 0.5 * kClutterBinSide;
  const Vector3d x = Vector3d::UnitX(), y = Vector3d::UnitY();
  for (const Vector3d& inward : {x, Vector3d(-x), y, Vector3d(-y)}) {
    engine::Obstacle wall;
    wall.name = fmt::format("wall{}", scene.obstacles.size());
    wall.shape = geometry::MakeHalfSpace(inward, -half);
    wall.friction = friction;
    scene.obstacles.push_back(std::move(wall));
  }
  for (int b = 0; b < boxes; ++b) {
    for (int o = 1; o < static_cast<int>(scene.obstacles.size()); ++o)
      scene.contacts.push_back(engine::ContactPair{b, o, friction});
  }
  engine::AddBodyPairs(scene);
  engine::ValidateScene(scene);
  return scene;
}

}  // namespace ecpsim::evaluation
