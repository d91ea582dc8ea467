#include "engine/contact_model.h"

#include <fmt/format.h>

#include "engine/step_report.h"

#include "engine/auto_model.h"
#include "engine/hull_model.h"
#include "engine/multipatch_model.h"
#include "engine/planar_model.h"
#include "engine/point_contact_model.h"

namespace ecpsim::engine {

std::unique_ptr<ContactModelStepper> MakeContactModel(const Scene& scene) {
  // the hull and point models have contacts between two moving hulls (the planar and
  // multi-patch models combine ECPs on one fixed plane)
  if (scene.model == ContactModel::kPlanar || scene.model == ContactModel::kMultiPatch) {
    for (const ContactPair& pair : scene.contacts) {
      if (!pair.WithBody()) continue;
      throw ModelInvalid(fmt::format(
          "{} model: bodies '{}' and '{}' can touch each other; the model handles contacts with "
          "fixed obstacles only; use --model hull (or exclude the pair under `pairs:`)",
          ContactModelName(scene.model), scene.bodies[pair.body].name,
          scene.bodies[pair.other_body].name));
    }
  }
  // a gripper's jaws move under the gripper's equations, which the hull model's MNCP carries
  if (!scene.grippers.empty() && scene.model != ContactModel::kHull &&
      scene.model != ContactModel::kAuto) {
    throw ModelInvalid(fmt::format(
        "{} model: gripper '{}' moves its jaws by equations of the hull model's step; use --model "
        "hull or auto",
        ContactModelName(scene.model), scene.grippers.front().name));
  }
  switch (scene.model) {
    case ContactModel::kPlanar:
      return std::make_unique<PlanarModel>(scene);
    case ContactModel::kMultiPatch:
      return std::make_unique<MultiPatchModel>(scene);
    case ContactModel::kPointLcp:
      return std::make_unique<PointContactModel>(scene);
    case ContactModel::kAuto:
      return std::make_unique<AutoModel>(scene);
    case ContactModel::kHull:
      break;
  }
  return std::make_unique<HullModel>(scene);
}

}  // namespace ecpsim::engine
