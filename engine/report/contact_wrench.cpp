#include "engine/report/contact_wrench.h"

namespace ecpsim::engine {

Wrench WrenchOnOther(const Scene& scene, const State& state, int k, double h) {
  const ContactPair& pair = scene.contacts[static_cast<size_t>(k)];
  const ContactState& c = state.contacts[static_cast<size_t>(k)];
  const Eigen::Vector3d reference = pair.WithBody()
                                        ? state.bodies[static_cast<size_t>(pair.other_body)].p_WB
                                        : Eigen::Vector3d::Zero();
  Wrench w;
  w.force = -(c.n * c.p_n + c.t * c.p_t + c.o * c.p_o) / h;
  w.moment = (c.a2 - reference).cross(w.force) - c.n * (c.p_r / h);
  return w;
}

}  // namespace ecpsim::engine
