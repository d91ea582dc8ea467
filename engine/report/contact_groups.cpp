#include "engine/report/contact_groups.h"

namespace ecpsim::engine {

using Eigen::Vector3d;

std::vector<ContactGroup> ContactGroups(const Scene& scene) {
  ContactIndex storage;
  return ContactIndexOf(scene, storage).groups;
}

ContactState CombinedContact(const State& state, const ContactGroup& group) {
  ContactState combined;
  if (group.end - group.first == 1) {
    const ContactState& c = state.contacts[group.first];
    combined.a1 = c.a1;
    combined.a2 = c.a2;
    combined.p_n = c.p_n;
    combined.p_t = c.p_t;
    combined.p_o = c.p_o;
    combined.p_r = c.p_r;
    combined.sigma = c.sigma;
    combined.n = c.n;
    combined.t = c.t;
    combined.o = c.o;
    return combined;
  }
  int dominant = group.first;
  double total_p_n = 0;
  for (int k = group.first; k < group.end; ++k) {
    const double p_n = state.contacts[k].p_n;
    if (p_n > state.contacts[dominant].p_n) dominant = k;
    if (p_n > 0) total_p_n += p_n;
  }
  const ContactState& frame = state.contacts[dominant];
  combined.n = frame.n;
  combined.t = frame.t;
  combined.o = frame.o;
  combined.a1 = frame.a1;
  combined.a2 = frame.a2;
  if (total_p_n > 0) {
    Vector3d a1 = Vector3d::Zero(), a2 = Vector3d::Zero();
    double sigma = 0;
    for (int k = group.first; k < group.end; ++k) {
      const ContactState& c = state.contacts[k];
      if (!(c.p_n > 0)) continue;
      a1 += c.p_n * c.a1;
      a2 += c.p_n * c.a2;
      sigma += c.p_n * c.sigma;
    }
    combined.a1 = a1 / total_p_n;
    combined.a2 = a2 / total_p_n;
    combined.sigma = sigma / total_p_n;
  }
  Vector3d force = Vector3d::Zero(), moment = Vector3d::Zero();
  for (int k = group.first; k < group.end; ++k) {
    const ContactState& c = state.contacts[k];
    const Vector3d f = c.n * c.p_n + c.t * c.p_t + c.o * c.p_o;
    force += f;
    moment += (c.a1 - combined.a1).cross(f) + c.n * c.p_r;
  }
  combined.p_n = combined.n.dot(force);
  combined.p_t = combined.t.dot(force);
  combined.p_o = combined.o.dot(force);
  combined.p_r = combined.n.dot(moment);
  return combined;
}

}  // namespace ecpsim::engine
