// The warm-start holder: a value of any model's type, held in place, copied deep, and destroyed
// exactly once.

#include "engine/warm_start.h"

#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "engine/models/hull_warm_start.h"
#include "engine/models/multipatch_warm_start.h"

namespace ecpsim::engine {
namespace {

// counts the values alive, to see that every one made is destroyed once
struct Counted {
  static inline int alive = 0;
  std::vector<int> data;
  Counted() { ++alive; }
  Counted(const Counted& other) : data(other.data) { ++alive; }
  Counted(Counted&& other) noexcept : data(std::move(other.data)) { ++alive; }
  Counted& operator=(const Counted&) = default;
  Counted& operator=(Counted&&) noexcept = default;
  ~Counted() { --alive; }
};

TEST(WarmStartTest, StartsEmptyAndGivesOnlyTheTypeItHolds) {
  WarmStart warm;
  EXPECT_TRUE(warm.empty());
  EXPECT_EQ(warm.Get<HullWarmStart>(), nullptr);
  warm.Emplace<HullWarmStart>().s = 0.25;
  EXPECT_FALSE(warm.empty());
  ASSERT_NE(warm.Get<HullWarmStart>(), nullptr);
  EXPECT_EQ(warm.Get<HullWarmStart>()->s, 0.25);
  EXPECT_EQ(warm.Get<MultiPatchWarmStart>(), nullptr);
  EXPECT_EQ(std::as_const(warm).Get<HullWarmStart>(), warm.Get<HullWarmStart>());
}

TEST(WarmStartTest, EmplaceKeepsAValueOfTheSameTypeAndReplacesAnother) {
  WarmStart warm;
  HullWarmStart& hull = warm.Emplace<HullWarmStart>();
  hull.window = {3, 5};
  EXPECT_EQ(&warm.Emplace<HullWarmStart>(), &hull);
  EXPECT_EQ(warm.Get<HullWarmStart>()->window, (std::vector<int>{3, 5}));
  warm.Emplace<MultiPatchWarmStart>().parts.resize(2);
  EXPECT_EQ(warm.Get<HullWarmStart>(), nullptr);
  EXPECT_EQ(warm.Get<MultiPatchWarmStart>()->parts.size(), 2u);
}

TEST(WarmStartTest, ACopyIsDeepAndACopyOverTheSameTypeReusesItsBuffers) {
  WarmStart warm;
  warm.Emplace<HullWarmStart>().window = {1, 2, 3};
  WarmStart copy = warm;
  copy.Get<HullWarmStart>()->window[0] = 9;
  EXPECT_EQ(warm.Get<HullWarmStart>()->window[0], 1);

  const int* buffer = copy.Get<HullWarmStart>()->window.data();
  copy = warm;
  EXPECT_EQ(copy.Get<HullWarmStart>()->window.data(), buffer);
  EXPECT_EQ(copy.Get<HullWarmStart>()->window, (std::vector<int>{1, 2, 3}));

  copy = WarmStart();
  EXPECT_TRUE(copy.empty());
  copy = copy;  // NOLINT: self-assignment keeps the value
  EXPECT_TRUE(copy.empty());
}

TEST(WarmStartTest, AMoveTakesTheBuffersAndLeavesAHolderThatCanBeReused) {
  WarmStart warm;
  warm.Emplace<HullWarmStart>().window = {4, 6};
  const int* buffer = warm.Get<HullWarmStart>()->window.data();
  WarmStart moved = std::move(warm);
  EXPECT_EQ(moved.Get<HullWarmStart>()->window.data(), buffer);
  WarmStart assigned;
  assigned.Emplace<MultiPatchWarmStart>();
  assigned = std::move(moved);
  EXPECT_EQ(assigned.Get<HullWarmStart>()->window.data(), buffer);
  warm.Emplace<HullWarmStart>().s = 1;  // a moved-from holder still works
  EXPECT_EQ(warm.Get<HullWarmStart>()->s, 1);
}

TEST(WarmStartTest, EveryValueMadeIsDestroyedOnce) {
  ASSERT_EQ(Counted::alive, 0);
  {
    WarmStart warm;
    warm.Emplace<Counted>().data = {1};
    WarmStart copy = warm;
    WarmStart moved = std::move(copy);
    EXPECT_EQ(Counted::alive, 3);
    warm.Reset();
    EXPECT_EQ(Counted::alive, 2);
    moved.Set(HullWarmStart{});  // replacing a value destroys it
    EXPECT_EQ(Counted::alive, 1);
    std::swap(copy, moved);
    EXPECT_EQ(Counted::alive, 1);
  }
  EXPECT_EQ(Counted::alive, 0);
}

}  // namespace
}  // namespace ecpsim::engine
