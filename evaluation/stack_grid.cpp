#include "evaluation/stack_grid.h"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/scene_io/scene_builders.h"

namespace ecpsim::evaluation {

engine::Scene MakeStackGrid(int bodies) {
  ECPSIM_DEMAND(bodies >= 1 && bodies <= kMaxGridBodies);
  const engine::Friction friction{0.5, 1, 1, 0.05};
  const int stacks = (bodies + kStackHeight - 1) / kStackHeight;
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(stacks))));
  // the grid's centre at the origin
  const double offset = 0.5 * (side - 1) * kStackSpacing;
  // one box copied: its hull is shared by all (a shared_ptr), its mesh copied
  engine::Body box = engine::MakeBoxBody(Eigen::Vector3d::Constant(kGridBoxSize), kGridBoxMass);
  box.friction = friction;
  std::vector<engine::Body> boxes;
  boxes.reserve(bodies);
  for (int i = 0; i < bodies; ++i) {
    const int stack = i / kStackHeight, level = i % kStackHeight;
    box.name = fmt::format("s{}b{}", stack, level);
    box.p0 = Eigen::Vector3d((stack % side) * kStackSpacing - offset,
                             (stack / side) * kStackSpacing - offset, (level + 0.5) * kGridBoxSize);
    boxes.push_back(box);
  }
  engine::Scene scene = engine::MakeGroundScene(std::move(boxes), kGridStep, friction);
  // the pairs within each stack: boxes i < j of one stack are consecutive in the body list
  for (int i = 0; i < bodies; ++i) {
    for (int j = i + 1; j < bodies && j / kStackHeight == i / kStackHeight; ++j) {
      scene.contacts.push_back(engine::BodyPair(scene, i, j, friction));
    }
  }
  engine::IndexContacts(scene);
  return scene;
}

}  // namespace ecpsim::evaluation
