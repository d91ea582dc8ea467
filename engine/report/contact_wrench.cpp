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

std::vector<int> SensedContacts(const Scene& scene, int body) {
  std::vector<int> sensed;
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    if (scene.contacts[k].other_body == body) sensed.push_back(static_cast<int>(k));
  return sensed;
}

Wrench SensorWrench(const Scene& scene, const State& state, int body) {
  Wrench total;
  for (int k : SensedContacts(scene, body)) {
    const Wrench w = WrenchOnOther(scene, state, k, scene.h);
    total.force += w.force;
    total.moment += w.moment;
  }
  return total;
}

}  // namespace ecpsim::engine
