#include "engine/scene.h"

#include <cmath>

namespace ecpsim::engine {

const char* ContactModelName(ContactModel model) {
  switch (model) {
    case ContactModel::kAuto:
      return "auto";
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

Friction PairFriction(const Friction& a, const Friction& b) {
  Friction f;
  f.mu = std::sqrt(a.mu * b.mu);
  f.e_t = std::sqrt(a.e_t * b.e_t);
  f.e_o = std::sqrt(a.e_o * b.e_o);
  f.e_r = std::sqrt(a.e_r * b.e_r);
  return f;
}

}  // namespace ecpsim::engine
