#include "engine/models/model_selection.h"

#include <fmt/format.h>

#include "engine/models/auto_model.h"
#include "engine/models/hull_model.h"
#include "engine/models/multipatch_model.h"
#include "engine/models/planar_model.h"
#include "engine/models/point_model.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

void UseContactModel(const Scene& scene, StepWorkspace& workspace,
                     const std::function<void(const ContactModelStepper&)>& use) {
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
      return use(PlanarModel(scene, workspace));
    case ContactModel::kMultiPatch:
      return use(MultiPatchModel(scene, workspace));
    case ContactModel::kPoint:
      return use(PointModel(scene, workspace));
    case ContactModel::kAuto:
      return use(AutoModel(scene, workspace));
    case ContactModel::kHull:
      break;
  }
  use(HullModel(scene, workspace));
}

}  // namespace ecpsim::engine
