#include "engine/contact_index.h"

#include <algorithm>
#include <memory>

#include "engine/scene.h"

namespace ecpsim::engine {

bool ContactIndex::Fits(const Scene& scene) const {
  return contacts == scene.contacts.size() && bodies == scene.bodies.size();
}

std::pair<const std::pair<int, int>*, const std::pair<int, int>*> ContactIndex::GroupsBetween(
    int a, int b) const {
  const std::pair<int, int>* begin = body_groups.data() + body_groups_begin[a];
  const std::pair<int, int>* end = body_groups.data() + body_groups_begin[a + 1];
  const auto first = std::lower_bound(begin, end, std::make_pair(b, 0));
  const auto last = std::lower_bound(first, end, std::make_pair(b + 1, 0));
  return {first, last};
}

void BuildContactIndex(const Scene& scene, ContactIndex& index) {
  const std::vector<ContactPair>& contacts = scene.contacts;
  const int n = static_cast<int>(scene.bodies.size());
  index.contacts = contacts.size();
  index.bodies = scene.bodies.size();
  index.groups.clear();
  index.row_first.clear();
  index.obstacle_groups.clear();
  index.chooses_sides = false;
  index.body_groups_begin.assign(n + 1, 0);
  for (size_t k = 0; k < contacts.size();) {
    const ContactPair& pair = contacts[k];
    ContactGroup group;
    group.first = static_cast<int>(k);
    group.rows_begin = static_cast<int>(index.row_first.size());
    size_t end = k;
    while (end < contacts.size() && contacts[end].SameBodies(pair)) {
      const ContactPair& c = contacts[end];
      if (end == k || c.sides != contacts[end - 1].sides || c.part != contacts[end - 1].part)
        index.row_first.push_back(static_cast<int>(end));
      ++end;
    }
    group.end = static_cast<int>(end);
    group.rows_end = static_cast<int>(index.row_first.size());
    index.chooses_sides = index.chooses_sides || pair.sides != SideChoice::kFixed;
    const int g = static_cast<int>(index.groups.size());
    index.groups.push_back(group);
    if (pair.WithBody()) {
      ++index.body_groups_begin[pair.body + 1];
      ++index.body_groups_begin[pair.other_body + 1];
    } else {
      index.obstacle_groups.push_back(g);
    }
    k = end;
  }
  // each body's groups with other bodies, counted above: a prefix sum makes begin[b + 1] the end
  // of b's range, each group placed below it moves it down to b's start, and a shift by one
  // makes each start its body's
  std::vector<int>& begin = index.body_groups_begin;
  for (int b = 0; b < n; ++b) begin[b + 1] += begin[b];
  index.body_groups.resize(begin[n]);
  for (size_t g = 0; g < index.groups.size(); ++g) {
    const ContactPair& pair = contacts[index.groups[g].first];
    if (!pair.WithBody()) continue;
    index.body_groups[--begin[pair.body + 1]] = {pair.other_body, static_cast<int>(g)};
    index.body_groups[--begin[pair.other_body + 1]] = {pair.body, static_cast<int>(g)};
  }
  for (int b = 0; b < n; ++b) begin[b] = begin[b + 1];
  begin[n] = static_cast<int>(index.body_groups.size());
  for (int b = 0; b < n; ++b) {
    std::sort(index.body_groups.begin() + index.body_groups_begin[b],
              index.body_groups.begin() + index.body_groups_begin[b + 1]);
  }
}

const ContactIndex& ContactIndexOf(const Scene& scene, ContactIndex& storage) {
  if (scene.contact_index != nullptr && scene.contact_index->Fits(scene))
    return *scene.contact_index;
  BuildContactIndex(scene, storage);
  return storage;
}

void IndexContacts(Scene& scene) {
  auto index = std::make_shared<ContactIndex>();
  BuildContactIndex(scene, *index);
  scene.contact_index = std::move(index);
}

}  // namespace ecpsim::engine
