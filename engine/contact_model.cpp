#include "engine/contact_model.h"

#include "engine/hull_model.h"
#include "engine/multipatch_model.h"
#include "engine/planar_model.h"
#include "engine/point_contact_model.h"

namespace ecpsim::engine {

std::unique_ptr<ContactModelStepper> MakeContactModel(const Scene& scene) {
  switch (scene.model) {
    case ContactModel::kPlanar:
      return std::make_unique<PlanarModel>(scene);
    case ContactModel::kMultiPatch:
      return std::make_unique<MultiPatchModel>(scene);
    case ContactModel::kPointLcp:
      return std::make_unique<PointContactModel>(scene);
    case ContactModel::kHull:
      break;
  }
  return std::make_unique<HullModel>(scene);
}

}  // namespace ecpsim::engine
