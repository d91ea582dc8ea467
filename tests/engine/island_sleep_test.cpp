// Sleeping islands (engine/island_sleep.h, engine/README.md "Sleeping islands"): a sleeping
// island's trajectory is the awake one's on every shipped scene, and an island at rest is woken
// by a body that lands on it, a kinematic body that pushes it and a load that starts later.

#include "engine/island_sleep.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/report/state_record.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;

// m: the issue's bar for a sleeping island's trajectory against the awake one's
constexpr double kSameTrajectory = 1e-12;

// A scene run twice side by side, sleeping on and off: the largest gaps between the two runs'
// positions (m) and orientations (quaternion coefficients), and per step the sleeping run's
// bodies that slept.
struct SideBySide {
  double position_gap = 0;
  double rotation_gap = 0;
  std::vector<int> sleeping;
  State asleep, awake;  // after the last step
};

SideBySide RunSleepingAndAwake(const Scene& scene, int steps) {
  Scene sleeping = scene, awake = scene;
  sleeping.solver.sleep = true;
  awake.solver.sleep = false;
  SideBySide run;
  run.asleep = InitialState(sleeping);
  run.awake = InitialState(awake);
  StepWorkspace asleep_workspace, awake_workspace;
  for (int k = 0; k < steps; ++k) {
    const StepReport report = Step(sleeping, run.asleep, asleep_workspace);
    const StepReport awake_report = Step(awake, run.awake, awake_workspace);
    EXPECT_EQ(awake_report.sleeping_bodies, 0);
    run.sleeping.push_back(report.sleeping_bodies);
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      const BodyState& s = run.asleep.bodies[b];
      const BodyState& a = run.awake.bodies[b];
      run.position_gap = std::max(run.position_gap, (s.p_WB - a.p_WB).norm());
      run.rotation_gap =
          std::max(run.rotation_gap, (s.Q_WB.coeffs() - a.Q_WB.coeffs()).cwiseAbs().maxCoeff());
    }
  }
  return run;
}

Scene SceneOf(const std::string& yaml) {
  return LoadSceneText(yaml, "island_sleep_test", ECPSIM_SOURCE_DIR).scene;
}

// two boxes stacked on the ground at rest, μ = 0.5 everywhere, and `more` (YAML list entries)
std::string StackWith(const std::string& more, const std::string& loads = "") {
  return fmt::format(R"(
gravity: [0, 0, -9.8]
h: 0.01
duration: 1
ground: {{friction: {{mu: 0.5}}}}
bodies:
  - name: bottom
    shape: {{box: {{size: [0.2, 0.2, 0.1]}}}}
    mass: 2
    friction: {{mu: 0.5}}
    position: [0, 0, 0.05]
  - name: top
    shape: {{box: {{size: [0.1, 0.1, 0.1]}}}}
    mass: 1
    friction: {{mu: 0.5}}
    position: [0, 0, 0.15]
{}
{}
)",
                     more, loads);
}

// steps of each shipped scene: of those whose steps cost seconds, the dominoes' first 0.3 s (d1
// meets d2 at 0.15 s and wakes it, d2 meets d3 at 0.26 s), the train's strike (the
// TrajectoryHash test's 10 steps) and the pyramid's first 0.6 s at rest; 300 steps (3 s at the usual h) of every other, past the drops' landings
int ShippedSteps(const std::string& name, const Scene& scene) {
  static const std::map<std::string, int> shortened = {
      {"dominoes.yaml", 60}, {"train.yaml", 10}, {"pyramid.yaml", 60}};
  const auto it = shortened.find(name);
  if (it != shortened.end()) return it->second;
  return std::min(300, static_cast<int>(std::ceil(scene.duration / scene.h - 1e-9)));
}

TEST(IslandSleepTest, EveryShippedSceneSleepsOnTheAwakeTrajectory) {
  std::vector<fs::path> paths;
  for (const auto& entry : fs::directory_iterator(fs::path(ECPSIM_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() == ".yaml") paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  ASSERT_GE(paths.size(), 12u);
  for (const fs::path& path : paths) {
    const std::string name = path.filename().string();
    const Scene scene = LoadScene(path.string()).scene;
    const SideBySide run = RunSleepingAndAwake(scene, ShippedSteps(name, scene));
    EXPECT_LE(run.position_gap, kSameTrajectory) << name;
    EXPECT_LE(run.rotation_gap, kSameTrajectory) << name;
    const int slept = std::accumulate(run.sleeping.begin(), run.sleeping.end(), 0);
    // the scenes that come to rest sleep (else the comparison would say nothing of sleeping)
    if (name == "stack.yaml" || name == "dominoes.yaml" || name == "tbar_push.yaml") {
      EXPECT_GT(slept, 0) << name;
    }
    RecordProperty(name + "_sleeping_body_steps", slept);
    RecordProperty(name + "_position_gap", fmt::format("{:.3g}", run.position_gap));
  }
}

TEST(IslandSleepTest, AStackSleepsUntilABoxLandsOnItAndSleepsAgainAfter) {
  // a box released 0.2 m above the stack lands at t = √(2 · 0.2 / g) ≈ 0.2 s
  const Scene scene = SceneOf(StackWith(R"(
  - name: falling
    shape: {box: {size: [0.1, 0.1, 0.1]}}
    mass: 1
    friction: {mu: 0.5}
    position: [0, 0, 0.45])"));
  const SideBySide run = RunSleepingAndAwake(scene, 80);
  EXPECT_LE(run.position_gap, kSameTrajectory);
  EXPECT_LE(run.rotation_gap, kSameTrajectory);
  // asleep from step 11 (10 steps at rest after the first), the falling box never
  EXPECT_EQ(run.sleeping[0], 0);
  EXPECT_EQ(run.sleeping[12], 2);
  // woken as the falling box's reach meets the top box (its island merges), before it lands
  const auto woken = std::find(run.sleeping.begin() + 12, run.sleeping.end(), 0);
  ASSERT_NE(woken, run.sleeping.end());
  EXPECT_LE(woken - run.sleeping.begin(), 21);
  // the box landed on the stack (the top box's CM 0.1 m below its own), and the three sleep
  EXPECT_NEAR(run.asleep.bodies[2].p_WB.z(), 0.25, 1e-9);
  EXPECT_EQ(*std::max_element(run.sleeping.end() - 20, run.sleeping.end()), 3);
}

TEST(IslandSleepTest, AKinematicPusherWakesTheStackItReaches) {
  // a plate at 0.1 m/s whose face starts 2 cm from the bottom box's: it arrives at t = 0.2 s
  const Scene scene = SceneOf(StackWith(R"(
  - name: pusher
    kinematic: true
    shape: {box: {size: [0.02, 0.2, 0.06]}}
    motion:
      velocity:
        position: [-0.13, 0, 0.04]
        linear: [0.1, 0, 0])"));
  const SideBySide run = RunSleepingAndAwake(scene, 60);
  EXPECT_LE(run.position_gap, kSameTrajectory);
  EXPECT_LE(run.rotation_gap, kSameTrajectory);
  EXPECT_EQ(run.sleeping[12], 2);
  // awake from the step the pusher's contact enters, and for as long as it pushes
  const auto woken = std::find(run.sleeping.begin() + 12, run.sleeping.end(), 0);
  ASSERT_NE(woken, run.sleeping.end());
  EXPECT_LT(woken - run.sleeping.begin(), 20);
  EXPECT_TRUE(std::all_of(woken, run.sleeping.end(), [](int n) { return n == 0; }));
  // the stack is pushed along: the bottom box 4 cm at the end (0.6 s)
  EXPECT_NEAR(run.asleep.bodies[0].p_WB.x(), 0.04, 0.002);
}

TEST(IslandSleepTest, ALoadThatStartsLaterWakesItsIslandAtItsStart) {
  // 20 N on the bottom box from t = 0.3 s: more than the ground's μ (m_1 + m_2) g = 14.7 N
  const Scene scene = SceneOf(StackWith("", R"(
loads:
  - body: bottom
    force: [20, 0, 0]
    start: 0.3)"));
  const SideBySide run = RunSleepingAndAwake(scene, 50);
  EXPECT_LE(run.position_gap, kSameTrajectory);
  EXPECT_LE(run.rotation_gap, kSameTrajectory);
  // asleep until the step that starts at 0.3 s (the 31st), awake from it on
  EXPECT_EQ(run.sleeping[29], 2);
  EXPECT_EQ(run.sleeping[30], 0);
  EXPECT_TRUE(std::all_of(run.sleeping.begin() + 30, run.sleeping.end(),
                          [](int n) { return n == 0; }));
  EXPECT_GT(run.asleep.bodies[0].p_WB.x(), 1e-3);
}

TEST(IslandSleepTest, ALoadThatVariesWithTimeNeverLetsItsIslandSleep) {
  // a sideways force growing from 0 to 2 N, far below the friction: the stack stays at rest, but
  // its load changes every step
  const Scene scene = SceneOf(StackWith("", R"(
loads:
  - body: top
    force: ["2*t", 0, 0])"));
  const SideBySide run = RunSleepingAndAwake(scene, 60);
  EXPECT_EQ(run.position_gap, 0);
  EXPECT_TRUE(std::all_of(run.sleeping.begin(), run.sleeping.end(), [](int n) { return n == 0; }));
}

TEST(IslandSleepTest, AStateRecordCarriesTheRestSoARestoredRunSleepsAsTheOriginal) {
  Scene scene = SceneOf(StackWith(""));
  scene.solver.sleep = true;
  State original = InitialState(scene);
  StepWorkspace workspace;
  for (int k = 0; k < 40; ++k) Step(scene, original, workspace);
  State restored = StateFromRecord(StateRecord(original), "record");
  ASSERT_EQ(restored.rest.steps, original.rest.steps);
  ASSERT_EQ(restored.rest.models, original.rest.models);
  ASSERT_EQ(restored.rest.in_step, original.rest.in_step);
  StepWorkspace restored_workspace;
  for (int k = 0; k < 40; ++k) {
    const StepReport a = Step(scene, original, workspace);
    const StepReport b = Step(scene, restored, restored_workspace);
    // asleep but on every 32nd step of rest, in both alike
    EXPECT_EQ(a.sleeping_bodies, b.sleeping_bodies) << k;
    EXPECT_EQ(a.sleeping_bodies, original.rest.steps[0] % kSleepCheckSteps == 1 ? 0 : 2) << k;
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
      EXPECT_EQ(original.bodies[i].p_WB, restored.bodies[i].p_WB);
      EXPECT_EQ(original.bodies[i].Q_WB.coeffs(), restored.bodies[i].Q_WB.coeffs());
    }
  }
  // a record without the rest (written before sleeping islands) reads as every body awake
  nlohmann::json record = StateRecord(original);
  record.erase("rest");
  EXPECT_TRUE(StateFromRecord(record, "record").rest.steps.empty());
}

// the differences of two flag vectors, at a block's ends, alone in a block and in the last,
// short block, as a plain loop finds them
TEST(IslandSleepTest, ForEachDifferenceFindsEveryDifferingFlagInOrder) {
  constexpr size_t kFlags = 1000;
  std::vector<char> a(kFlags, 0), b(kFlags, 0);
  for (size_t k : {0u, 255u, 256u, 511u, 700u, 701u, 999u}) b[k] = 1;
  for (size_t k = 300; k < 310; ++k) a[k] = b[k] = 1;  // set in both: no difference
  a[800] = 1;
  std::vector<size_t> expected, found;
  for (size_t k = 0; k < kFlags; ++k)
    if (a[k] != b[k]) expected.push_back(k);
  ForEachDifference(a, b, [&](size_t k) { found.push_back(k); });
  EXPECT_EQ(found, expected);
  EXPECT_EQ(found.size(), 8u);
  found.clear();
  ForEachDifference(a, a, [&](size_t k) { found.push_back(k); });
  EXPECT_TRUE(found.empty());
}

TEST(IslandSleepTest, ABodyIsAtRestBelowATenQuadrillionthOfItsLengthAStep) {
  // a 0.1 m cube: radius of gyration √(3 · 0.1² / 6) = 0.0707 m
  Body cube;
  cube.mass = 1;
  cube.inertia = Eigen::Matrix3d::Identity() * (0.1 * 0.1 / 6);
  const double length = std::sqrt(0.1 * 0.1 / 2);
  const double h = 0.01;
  BodyState state;
  state.v_WB = Eigen::Vector3d(0.99 * kRestFraction * length / h, 0, 0);
  EXPECT_TRUE(AtRest(cube, state, h));
  state.v_WB.x() = 1.01 * kRestFraction * length / h;
  EXPECT_FALSE(AtRest(cube, state, h));
  state.v_WB.setZero();
  state.w_WB = Eigen::Vector3d(0, 0, 0.99 * kRestFraction / h);
  EXPECT_TRUE(AtRest(cube, state, h));
  state.w_WB.z() = 1.01 * kRestFraction / h;
  EXPECT_FALSE(AtRest(cube, state, h));
}

}  // namespace
}  // namespace ecpsim::engine
