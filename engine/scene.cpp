#include "engine/scene.h"

namespace ecpsim::engine {

const char* ContactModelName(ContactModel model) {
  switch (model) {
    case ContactModel::kHull:
      return "hull";
    case ContactModel::kPlanar:
      return "planar";
    case ContactModel::kMultiPatch:
      return "multipatch";
    case ContactModel::kPointLcp:
      return "point";
  }
  return "unknown";
}

}  // namespace ecpsim::engine
