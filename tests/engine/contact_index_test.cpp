// The contact index (engine/contact_index.h): where each pair of bodies' contacts lie, checked
// against the contact list of every shipped scene; the routes that build scenes index them; and a
// step of a scene without its index, which indexes it itself, is the step with it, to the bit.

#include "engine/contact_index.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "engine/scene.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> ShippedScenes() {
  std::vector<std::string> paths;
  for (const auto& entry : fs::directory_iterator(std::string(ECPSIM_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() == ".yaml") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// every property the broad phase relies on, each contact and group checked against the list
void ExpectIndexes(const Scene& scene, const ContactIndex& index) {
  ASSERT_TRUE(index.Fits(scene));
  const std::vector<ContactPair>& contacts = scene.contacts;
  int next = 0;
  std::vector<std::vector<std::pair<int, int>>> body_groups(scene.bodies.size());
  std::vector<int> obstacle_groups;
  for (size_t g = 0; g < index.groups.size(); ++g) {
    const ContactGroup& group = index.groups[g];
    // the groups cover the list in order, each a maximal run of one pair of sides
    ASSERT_EQ(group.first, next);
    ASSERT_LT(group.first, group.end);
    for (int k = group.first; k < group.end; ++k)
      EXPECT_TRUE(contacts[k].SameBodies(contacts[group.first]));
    if (group.end < static_cast<int>(contacts.size())) {
      EXPECT_FALSE(contacts[group.end].SameBodies(contacts[group.first]));
    }
    next = group.end;
    // its rows: from its first contact to its end, each one side choice and one side of F
    ASSERT_LT(group.rows_begin, group.rows_end);
    EXPECT_EQ(index.row_first[group.rows_begin], group.first);
    for (int r = group.rows_begin; r < group.rows_end; ++r) {
      const int begin = index.row_first[r];
      const int end = r + 1 < group.rows_end ? index.row_first[r + 1] : group.end;
      ASSERT_LT(begin, end);
      for (int k = begin; k < end; ++k) {
        EXPECT_EQ(contacts[k].part, contacts[begin].part);
        EXPECT_EQ(contacts[k].sides, contacts[begin].sides);
      }
      if (r > group.rows_begin) {
        const ContactPair& before = contacts[begin - 1];
        EXPECT_TRUE(before.part != contacts[begin].part || before.sides != contacts[begin].sides);
      }
    }
    const ContactPair& pair = contacts[group.first];
    if (pair.WithBody()) {
      body_groups[pair.body].emplace_back(pair.other_body, static_cast<int>(g));
      body_groups[pair.other_body].emplace_back(pair.body, static_cast<int>(g));
    } else {
      obstacle_groups.push_back(static_cast<int>(g));
    }
  }
  EXPECT_EQ(next, static_cast<int>(contacts.size()));
  EXPECT_EQ(index.obstacle_groups, obstacle_groups);
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    std::sort(body_groups[b].begin(), body_groups[b].end());
    const std::vector<std::pair<int, int>> listed(
        index.body_groups.begin() + index.body_groups_begin[b],
        index.body_groups.begin() + index.body_groups_begin[b + 1]);
    EXPECT_EQ(listed, body_groups[b]) << "body " << b;
    // and each pair of bodies' groups, from either side
    for (const auto& [other, g] : body_groups[b]) {
      const auto [first, last] = index.GroupsBetween(static_cast<int>(b), other);
      EXPECT_TRUE(std::find(first, last, std::make_pair(other, g)) != last);
      for (auto it = first; it != last; ++it) EXPECT_EQ(it->first, other);
    }
  }
}

TEST(ContactIndexTest, EveryShippedSceneIsIndexedWhereItsContactsLie) {
  const std::vector<std::string> scenes = ShippedScenes();
  ASSERT_GE(scenes.size(), 10u);
  for (const std::string& path : scenes) {
    SCOPED_TRACE(path);
    const LoadedScene loaded = LoadScene(path);
    ASSERT_NE(loaded.scene.contact_index, nullptr);
    ExpectIndexes(loaded.scene, *loaded.scene.contact_index);
  }
}

TEST(ContactIndexTest, ABodyOfPartsHasARowPerPartAndItsHullsSetFirstUnderAuto) {
  // the round mug of 36 parts under `decomposition: auto` and the cube: the hulls' contact (one
  // row), then a row per part of the mug, whichever body F is
  const LoadedScene loaded = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/cube_in_mug.yaml",
                                       {"bodies.0.mesh=meshes/round_mug.obj"});
  const Scene& scene = loaded.scene;
  const ContactIndex& index = *scene.contact_index;
  const auto [first, last] = index.GroupsBetween(0, 1);
  ASSERT_EQ(last - first, 1);
  const ContactGroup& group = index.groups[first->second];
  const int parts = static_cast<int>(scene.bodies[0].parts.size());
  ASSERT_GT(parts, 1);
  EXPECT_EQ(group.end - group.first, 1 + parts);
  // F the mug (body 0, the lower index): a row per part, each against the cube's hull
  ASSERT_EQ(scene.contacts[group.first].body, 0);
  EXPECT_EQ(group.rows_end - group.rows_begin, 1 + parts);
  EXPECT_EQ(scene.contacts[group.first].sides, SideChoice::kHulls);
}

TEST(ContactIndexTest, TheBuildersIndexTheirScenesAndAnAddedPairUnfitsTheIndex) {
  std::vector<Body> boxes;
  for (int i = 0; i < 3; ++i) {
    boxes.push_back(testing::MakeBoxBody(Eigen::Vector3d::Constant(0.1), 1, std::to_string(i)));
    boxes.back().p0 = Eigen::Vector3d(0.3 * i, 0, 0.05);
  }
  Scene scene = MakeGroundScene(boxes, 0.01, Friction{});
  ASSERT_NE(scene.contact_index, nullptr);
  ExpectIndexes(scene, *scene.contact_index);
  AddBodyPairs(scene);
  ExpectIndexes(scene, *scene.contact_index);
  EXPECT_EQ(scene.contact_index->body_groups.size(), 6u);  // three pairs, each seen from both
  scene.contacts.push_back(BodyPair(scene, 0, 2, Friction{}));
  EXPECT_FALSE(scene.contact_index->Fits(scene));
  ContactIndex own;
  BuildContactIndex(scene, own);
  ExpectIndexes(scene, own);
  // two groups of bodies 0 and 2, found in order
  const auto [first, last] = own.GroupsBetween(2, 0);
  ASSERT_EQ(last - first, 2);
  EXPECT_LT(first[0].second, first[1].second);
}

// the trajectory's every bit: bodies' poses and velocities, contacts' impulses and ECPs
void ExpectSameState(const State& a, const State& b) {
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].p_WB, b.bodies[i].p_WB);
    EXPECT_EQ(a.bodies[i].Q_WB.coeffs(), b.bodies[i].Q_WB.coeffs());
    EXPECT_EQ(a.bodies[i].v_WB, b.bodies[i].v_WB);
    EXPECT_EQ(a.bodies[i].w_WB, b.bodies[i].w_WB);
  }
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (size_t k = 0; k < a.contacts.size(); ++k) {
    EXPECT_EQ(a.contacts[k].p_n, b.contacts[k].p_n);
    EXPECT_EQ(a.contacts[k].a1, b.contacts[k].a1);
  }
}

TEST(ContactIndexTest, AStepIndexingItsSceneItselfIsTheStepWithTheScenesIndex) {
  // bodies of parts choosing their sets (the mug), a pile (the dominoes)
  for (const char* name : {"cube_in_mug.yaml", "dominoes.yaml"}) {
    SCOPED_TRACE(name);
    const Scene indexed = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + name).scene;
    Scene bare = indexed;
    bare.contact_index = nullptr;
    State a = InitialState(indexed), b = InitialState(bare);
    // 0.4 s at h = 0.005 s: the cube falls into the mug and lands, the first domino lands on the
    // second (0.34 s)
    constexpr int kSteps = 80;
    for (int k = 0; k < kSteps; ++k) {
      ASSERT_TRUE(Step(indexed, a).converged);
      ASSERT_TRUE(Step(bare, b).converged);
    }
    ExpectSameState(a, b);
  }
}

}  // namespace
}  // namespace ecpsim::engine
