#include "engine/island_threads.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/islands.h"
#include "engine/models/model_selection.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/solver/complementarity_solver.h"
#include "engine/step_driver.h"
#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using ::testing::HasSubstr;

// every item in `order` handled once, on whichever thread took it
std::vector<int> TimesHandled(IslandThreads& threads, int count) {
  std::vector<int> order(count);
  for (int i = 0; i < count; ++i) order[i] = count - 1 - i;
  std::vector<std::atomic<int>> handled(count);
  StepWorkspace caller;
  threads.ForEach(order, caller, [&](StepWorkspace&, const IslandThreads::TakeItem& take) {
    for (int i; take(i);) handled[i].fetch_add(1);
  });
  std::vector<int> times;
  for (const std::atomic<int>& h : handled) times.push_back(h.load());
  return times;
}

TEST(IslandThreadsTest, EveryItemIsHandledOnceWhateverTheThreadCount) {
  IslandThreads threads;
  for (int n : {1, 2, 3, 1, 4}) {
    threads.SetThreads(n);
    EXPECT_EQ(threads.threads(), n);
    // many jobs in a row: a worker waking late for one must not take the next one's items twice
    for (int job = 0; job < 200; ++job) {
      const int count = job % 7;
      EXPECT_EQ(TimesHandled(threads, count), std::vector<int>(count, 1))
          << n << " threads, job " << job;
    }
  }
}

TEST(IslandThreadsTest, EachThreadWorksInItsOwnWorkspace) {
  IslandThreads threads;
  threads.SetThreads(3);
  StepWorkspace caller;
  std::vector<int> order(64);
  for (int i = 0; i < 64; ++i) order[i] = i;
  // each item records its workspace's address while a slow item holds its thread: no two
  // threads ever share one, and the caller's is the caller's
  std::vector<const StepWorkspace*> used(64);
  std::atomic<int> callers_items{0};
  threads.ForEach(order, caller,
                  [&](StepWorkspace& workspace, const IslandThreads::TakeItem& take) {
                    int& depth = workspace.Part<int>();
                    for (int i; take(i);) {
                      EXPECT_EQ(depth++, 0) << "a workspace used by two threads at once";
                      used[i] = &workspace;
                      if (&workspace == &caller) callers_items.fetch_add(1);
                      volatile double x = 0;
                      for (int k = 0; k < 20000; ++k) x = x + k;
                      --depth;
                    }
                  });
  for (const StepWorkspace* w : used) EXPECT_NE(w, nullptr);
  EXPECT_GE(callers_items.load(), 1);
}

TEST(IslandThreadsTest, WhatAThreadThrowsReachesTheCallerAfterEveryThreadIsDone) {
  IslandThreads threads;
  threads.SetThreads(2);
  StepWorkspace caller;
  const std::vector<int> order = {0, 1, 2, 3, 4, 5, 6, 7};
  std::atomic<int> done{0};
  EXPECT_THAT(
      [&] {
        threads.ForEach(order, caller, [&](StepWorkspace&, const IslandThreads::TakeItem& take) {
          for (int i; take(i);) {
            if (i == 5) throw std::runtime_error("item 5");
            done.fetch_add(1);
          }
        });
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("item 5")));
  // the thread that threw took no more items; the other handled the rest of them
  EXPECT_GE(done.load(), 1);
  EXPECT_LE(done.load(), 7);
  // and the threads take the next job as ever
  EXPECT_EQ(TimesHandled(threads, 5), std::vector<int>(5, 1));
}

TEST(IslandThreadsTest, ANumberOfThreadsBelowOneIsRefused) {
  IslandThreads threads;
  EXPECT_THAT([&] { threads.SetThreads(0); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("threads = 0: expected")));
  EXPECT_EQ(threads.threads(), 1);
}

// Twelve boxes in islands of one to three: three stacks of two and three dropped turned on
// each other, singles sliding and spinning, all landing within the first steps, so that the
// islands differ in size and in cost and merge and split as the bodies meet.
// m: the CM height of box `column + 6 level` (edge 0.05 + 0.004 i, sides 1, 0.9, 0.8 of it; its
// half-diagonal under 0.8 of the edge): clear of the ground, the upper box clear of the lower
double Height(int column, int level) {
  const double lower = 0.05 + 0.004 * column, upper = lower + 0.024;
  const double z0 = 0.8 * lower + 0.002;
  return level == 0 ? z0 : z0 + 0.8 * (lower + upper) + 0.002 * (column + 1);
}

Scene IslandsOfManySizes() {
  std::string bodies;
  for (int i = 0; i < 12; ++i) {
    const int column = i % 6, level = i / 6;
    const double size = 0.05 + 0.004 * i;
    bodies += fmt::format(
        "  - {{name: b{}, shape: {{box: {{size: [{}, {}, {}]}}}}, mass: {}, friction: {{mu: 0.4, "
        "e_r: 0.02}}, position: [{}, {}, {}], rpy: [{}, {}, {}], velocity: [{}, 0, 0], "
        "angular_velocity: [0, 0, {}]}}\n",
        i, size, 0.9 * size, 0.8 * size, 0.2 + 0.05 * i, 0.3 * column, 0.01 * level,
        Height(column, level), 3 * i, -2 * i, 7 * i, 0.1 * (i % 3), 0.5 * (i % 4));
  }
  const std::string text =
      "h: 0.005\nduration: 0.3\nground:\n  friction: {mu: 0.4, e_r: 0.02}\n"
      "bodies:\n" +
      bodies;
  return LoadSceneText(text, "islands_of_many_sizes.yaml", ".").scene;
}

TEST(IslandThreadsTest, AStepOnAnyNumberOfThreadsIsTheStepOnOne) {
  const Scene scene = IslandsOfManySizes();
  std::vector<State> states;
  std::vector<StepReport> reports;
  for (int n : {1, 2, 3}) {
    StepWorkspace workspace;
    IslandThreadsOf(workspace).SetThreads(n);
    State state = InitialState(scene);
    StepReport report;
    int most_islands = 0;
    for (int step = 0; step < 60; ++step) {
      most_islands = std::max(most_islands, static_cast<int>(FormIslands(scene, state).size()));
      report = Step(scene, state, workspace);
    }
    // (the scene's point: several islands to share)
    EXPECT_GE(most_islands, 6);
    states.push_back(state);
    reports.push_back(report);
  }
  for (size_t k = 1; k < states.size(); ++k) {
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      const BodyState &one = states[0].bodies[b], &many = states[k].bodies[b];
      EXPECT_EQ(one.p_WB, many.p_WB) << scene.bodies[b].name;
      EXPECT_EQ(one.Q_WB.coeffs(), many.Q_WB.coeffs()) << scene.bodies[b].name;
      EXPECT_EQ(one.v_WB, many.v_WB) << scene.bodies[b].name;
      EXPECT_EQ(one.w_WB, many.w_WB) << scene.bodies[b].name;
    }
    for (size_t c = 0; c < scene.contacts.size(); ++c) {
      EXPECT_EQ(states[0].contacts[c].p_n, states[k].contacts[c].p_n) << c;
      EXPECT_EQ(states[0].contacts[c].p_t, states[k].contacts[c].p_t) << c;
    }
    EXPECT_EQ(reports[0].iterations, reports[k].iterations);
    EXPECT_EQ(reports[0].residual, reports[k].residual);
    EXPECT_EQ(reports[0].models, reports[k].models);
  }
}

TEST(IslandThreadsTest, AStepStoppedByItsFlagThrowsCancelledAndLeavesTheState) {
  const Scene scene = IslandsOfManySizes();
  for (int n : {1, 2}) {
    StepWorkspace workspace;
    IslandThreadsOf(workspace).SetThreads(n);
    CancelFlag flag;
    StopStepsOn(workspace, &flag);
    State state = InitialState(scene);
    for (int step = 0; step < 10; ++step) Step(scene, state, workspace);
    const State before = state;
    flag.Raise();
    EXPECT_THROW(Step(scene, state, workspace), Cancelled) << n << " threads";
    EXPECT_EQ(state.steps, before.steps);
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      EXPECT_EQ(state.bodies[b].p_WB, before.bodies[b].p_WB);
      EXPECT_EQ(state.bodies[b].v_WB, before.bodies[b].v_WB);
    }
    // cleared, the step is the one a run that was never stopped takes
    flag.Clear();
    State uninterrupted = before;
    StepWorkspace fresh;
    Step(scene, state, workspace);
    Step(scene, uninterrupted, fresh);
    for (size_t b = 0; b < scene.bodies.size(); ++b)
      EXPECT_EQ(state.bodies[b].p_WB, uninterrupted.bodies[b].p_WB);
  }
}

TEST(IslandThreadsTest, EachThreadsSolvesStopOnTheCallersFlag) {
  // what each thread's stepper would solve in: its workspace's McpWorkspace watches the flag
  const Scene scene = IslandsOfManySizes();
  StepWorkspace workspace;
  IslandThreadsOf(workspace).SetThreads(3);
  CancelFlag flag;
  StopStepsOn(workspace, &flag);
  std::mutex mutex;
  std::vector<const CancelFlag*> seen;
  const WithModel with_model = [&](StepWorkspace& thread_workspace,
                                   const std::function<void(const ContactModelStepper&)>& use) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      seen.push_back(thread_workspace.Part<McpWorkspace>().cancel());
    }
    UseContactModel(scene, thread_workspace, use);
  };
  State state = InitialState(scene);
  StepIslands(scene, state, with_model, workspace);
  ASSERT_FALSE(seen.empty());
  for (const CancelFlag* watched : seen) EXPECT_EQ(watched, &flag);
}

// Moves every body by h along x, but refuses islands of bodies named "stubborn…" at every h
class RefusingModel final : public ContactModelStepper {
 public:
  explicit RefusingModel(const Scene& scene) : scene_(scene) {}
  AdvanceResult Advance(const Island& island, double, double h, IslandState& state,
                        Effort) const override {
    AdvanceResult result;
    result.iterations = 1;
    if (scene_.bodies[island.bodies[0]].name.rfind("stubborn", 0) == 0) {
      result.residual = 0.5;
      result.tried.push_back({"test", h, "refused"});
      return result;
    }
    for (BodyState& b : state.bodies) b.p_WB.x() += h;
    result.solved = true;
    return result;
  }

 private:
  const Scene& scene_;
};

TEST(IslandThreadsTest, AFailedStepNamesTheFirstFailingIslandWhicheverThreadMetIt) {
  std::vector<Body> bodies;
  for (const char* name : {"easy0", "easy1", "stubborn2", "easy3", "stubborn4", "easy5"}) {
    Body box = testing::MakeBoxBody(Eigen::Vector3d(0.1, 0.1, 0.1), 1);
    box.name = name;
    box.p0 = Eigen::Vector3d(static_cast<double>(bodies.size()), 0, 1);
    bodies.push_back(box);
  }
  const Scene scene = testing::MakeGroundScene(bodies);
  const RefusingModel model(scene);
  StepWorkspace workspace;
  IslandThreadsOf(workspace).SetThreads(2);
  const State before = InitialState(scene);
  for (int trial = 0; trial < 50; ++trial) {
    State state = before;
    try {
      StepIslands(
          scene, state,
          [&](StepWorkspace&, const std::function<void(const ContactModelStepper&)>& use) {
            use(model);
          },
          workspace);
      ADD_FAILURE() << "no SolverFailure";
    } catch (const SolverFailure& failure) {
      ASSERT_NE(failure.step_failure(), nullptr);
      EXPECT_EQ(failure.step_failure()->bodies, std::vector<std::string>{"stubborn2"});
    }
    EXPECT_EQ(state.steps, 0);
    EXPECT_EQ(state.bodies[0].p_WB, before.bodies[0].p_WB);
  }
}

}  // namespace
}  // namespace ecpsim::engine
