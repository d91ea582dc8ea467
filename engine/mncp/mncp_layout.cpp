#include "engine/mncp/mncp_layout.h"

#include "common/errors.h"

namespace ecpsim::engine {

using Eigen::Vector3d;

MncpLayout MakeLayout(const BodyProblem& problem) {
  std::vector<std::array<int, 2>> counts;
  for (const ContactProblem& cp : problem.contacts)
    counts.push_back({static_cast<int>(cp.window.size()), cp.obstacle->NumConstraints()});
  return LayOutContacts(6, counts);  // ν⁺ = (v⁺, ω⁺) first
}

MncpLayout LayOutContacts(int first, const std::vector<std::array<int, 2>>& counts) {
  MncpLayout layout;
  int next = first;
  layout.contacts.resize(counts.size());
  for (size_t k = 0; k < counts.size(); ++k) {
    auto& c = layout.contacts[k];
    const bool plane = counts[k][1] == 0;
    c.a1 = next;
    next += 3;
    c.a2 = plane ? -1 : next;
    c.s = plane ? -1 : next + 3;
    if (!plane) next += 4;
    c.p_t = next;
    c.p_o = next + 1;
    c.p_r = next + 2;
    next += 3;
  }
  layout.num_free = next;
  for (size_t k = 0; k < counts.size(); ++k) {
    auto& c = layout.contacts[k];
    c.l = next;
    c.l_count = counts[k][0];
    next += c.l_count;
    c.l_g_count = counts[k][1];
    c.l_g = next;  // (an empty range on a plane)
    next += c.l_g_count;
    c.p_n = next++;
    c.sigma = next++;
  }
  layout.size = next;
  return layout;
}

ContactGap ContactGapAt(const MncpLayout::Contact& L, const geometry::ConvexShape* plane,
                        const Eigen::VectorXd& z) {
  if (!L.on_plane()) return {z.segment<3>(L.a2), z[L.s]};
  ECPSIM_DEMAND(plane != nullptr);
  const Vector3d a1 = z.segment<3>(L.a1);
  const Vector3d N = plane->Gradient(0, a1);
  const double s = plane->Value(0, a1) / N.squaredNorm();
  return {a1 - s * N, s};
}

}  // namespace ecpsim::engine
