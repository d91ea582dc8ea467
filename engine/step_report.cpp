#include "engine/step_report.h"

namespace ecpsim::engine {

const char* StepModelName(StepModel model) {
  switch (model) {
    case StepModel::kFree:
      return "free";
    case StepModel::kPlanar:
      return "planar";
    case StepModel::kHull:
      return "hull";
    case StepModel::kMultiPatch:
      return "multipatch";
    case StepModel::kPoint:
      return "point";
    case StepModel::kKinematic:
      break;
  }
  return "kinematic";
}

}  // namespace ecpsim::engine
