#pragma once
// Where each pair of bodies' contacts lie in Scene::contacts, so that the broad phase reaches the
// contacts of the bodies it finds near each other without walking every potential pair
// (engine/README.md, "Broad phase and islands").

#include <cstddef>
#include <utility>
#include <vector>

namespace ecpsim::engine {

struct ContactPair;
struct Scene;

/// The consecutive contacts [first, end) of Scene::contacts that join the same body to the same
/// body or obstacle (ContactPair::SameBodies) — one contact alone where the two touch with their
/// hulls — in rows: consecutive contacts with one side choice and one side of F (its hull or a
/// part) against each side of G (AddBodyContacts).
struct ContactGroup {
  int first = 0, end = 0;
  int rows_begin = 0, rows_end = 0;  // its rows in ContactIndex::row_first
};

/// The groups of a scene's contacts, found per body: built once for a scene (IndexContacts) whose
/// contacts then stay as they are ("immutable once loaded"); a scene without one, or whose
/// contacts changed in number since, is indexed by the step into its workspace, every step.
struct ContactIndex {
  std::size_t contacts = 0, bodies = 0;  // the scene's sizes when indexed
  std::vector<ContactGroup> groups;      // in the order of their contacts
  std::vector<int> row_first;            // each row's first contact; a row ends at the next one's
  /// per body b, [body_groups_begin[b], body_groups_begin[b + 1]) of `body_groups`: (other body,
  /// group) of every group between b and another body, as F or as G, sorted by the other body
  std::vector<int> body_groups_begin;
  std::vector<std::pair<int, int>> body_groups;
  std::vector<int> obstacle_groups;  // the groups between a body and an obstacle, in order
  bool chooses_sides = false;  // whether a group lists its hulls' and its parts' contacts (kAuto)

  /// Whether the index was built for contacts and bodies as many as `scene`'s.
  bool Fits(const Scene& scene) const;
  /// The groups between bodies a and b (a ≠ b), in order.
  std::pair<const std::pair<int, int>*, const std::pair<int, int>*> GroupsBetween(int a,
                                                                                  int b) const;
};

/// `index` rebuilt for `scene`'s contacts, over its last contents (reusing their storage).
void BuildContactIndex(const Scene& scene, ContactIndex& index);

/// The scene's contact index where it has one that fits it, else one built into `storage`.
const ContactIndex& ContactIndexOf(const Scene& scene, ContactIndex& storage);

/// Gives `scene` its contact index (Scene::contact_index): for a scene whose contacts are
/// complete; each route that builds a scene (engine/scene_io, evaluation) calls it last.
void IndexContacts(Scene& scene);

}  // namespace ecpsim::engine
