#include "evaluation/scenario.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"
#include "evaluation/clutter_bin.h"
#include "tests/tolerances.h"

namespace ecpsim::evaluation {
namespace {

constexpr double kG = 9.8;

TEST(MeanRadiusOfRectangleTest, SquareHasItsClosedForm) {
  // mean distance from the centre of a unit square: (√2 + ln(1 + √2)) / 6
  const double expected = (std::sqrt(2.0) + std::log(1 + std::sqrt(2.0))) / 6;
  EXPECT_NEAR(MeanRadiusOfRectangle(1, 1), expected, kUnitRoundOff);
  EXPECT_NEAR(MeanRadiusOfRectangle(0.2, 0.2), 0.2 * expected, kUnitRoundOff);
}

TEST(MeanRadiusOfRectangleTest, MatchesAMidpointSumForAThinRectangle) {
  // 4000 × 500 midpoint cells of a 2 × 0.25 rectangle: the sum's error is O(cell²) ≈ 1e-7
  const double a = 2, b = 0.25;
  const int nx = 4000, ny = 500;
  double sum = 0;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      sum += std::hypot(((i + 0.5) / nx - 0.5) * a, ((j + 0.5) / ny - 0.5) * b);
    }
  }
  constexpr double kMidpointSumError = 1e-7;  // m
  EXPECT_NEAR(MeanRadiusOfRectangle(a, b), sum / (nx * ny), kMidpointSumError);
  // a thin strip's mean radius tends to a/4; at b = a/8 it is 0.0094 m above it
  constexpr double kThinStripLimit = 0.01;  // m
  EXPECT_NEAR(MeanRadiusOfRectangle(a, b), a / 4, kThinStripLimit);
}

class WorkPrecisionScenariosTest : public ::testing::Test {
 protected:
  const std::vector<Scenario> scenarios_ =
      WorkPrecisionScenarios(std::string(ECPSIM_SOURCE_DIR) + "/scenes", 0.5);
  const Scenario& Find(const std::string& name) {
    for (const Scenario& s : scenarios_) {
      if (s.name == name) return s;
    }
    ADD_FAILURE() << "no scenario " << name;
    return scenarios_.front();
  }
};

TEST_F(WorkPrecisionScenariosTest, NamesListThemInOrder) {
  std::vector<std::string> names;
  for (const Scenario& s : scenarios_) names.push_back(s.name);
  EXPECT_EQ(names, WorkPrecisionScenarioNames());
}

TEST_F(WorkPrecisionScenariosTest, SlideStopsAtTheCoulombDistance) {
  const Scenario& slide = Find("slide");
  const double mu = 0.3, v0 = 1;
  EXPECT_NEAR(slide.stop_time, v0 / (mu * kG), kUnitRoundOff);
  const engine::BodyState end = slide.analytic(slide.scene.duration);
  EXPECT_NEAR((end.p_WB - slide.scene.bodies[0].p0).norm(), v0 * v0 / (2 * mu * kG), kUnitRoundOff);
  EXPECT_LT(end.v_WB.norm(), kUnitRoundOff);
  // sliding at 30° to the box's edges
  EXPECT_NEAR(std::atan2(slide.scene.bodies[0].v0.y(), slide.scene.bodies[0].v0.x()),
              std::acos(-1.0) / 6, kUnitRoundOff);
}

TEST_F(WorkPrecisionScenariosTest, SpinTorsionIsTheFootprintsMeanRadius) {
  const Scenario& spin = Find("spin");
  const double r_mean = MeanRadiusOfRectangle(0.2, 0.2);
  EXPECT_DOUBLE_EQ(spin.scene.contacts[0].friction.e_r, r_mean);
  // ω falls at μ m g r̄ / I_zz and reaches 0 at stop_time
  const double alpha = 0.3 * 1 * kG * r_mean / spin.scene.bodies[0].inertia(2, 2);
  // s, rad/s: a few flops from the scene's inertia and mean radius, round-off with room
  constexpr double kDerivedRoundOff = 1e-12;
  EXPECT_NEAR(spin.stop_time, 10 / alpha, kDerivedRoundOff);
  EXPECT_NEAR(spin.analytic(spin.stop_time / 2).w_WB.z(), 5, kDerivedRoundOff);
}

TEST_F(WorkPrecisionScenariosTest, ConvergedScenesAreCutAndFlagged) {
  for (const char* name : {"desk", "tbar", "dumbbell", "tbar_push"}) {
    const Scenario& s = Find(name);
    EXPECT_FALSE(s.analytic) << name;
    EXPECT_DOUBLE_EQ(s.scene.duration, 0.5) << name;
  }
  // the finger pushes the T-bar, which is measured
  const Scenario& push = Find("tbar_push");
  EXPECT_EQ(push.scene.bodies[push.body].name, "tbar");
  EXPECT_TRUE(push.scene.bodies[1 - push.body].IsKinematic());
  EXPECT_TRUE(Find("desk").planar_applies);
  EXPECT_TRUE(Find("desk").multipatch_applies);  // its four legs are parts
  EXPECT_FALSE(Find("tbar").planar_applies);
  EXPECT_FALSE(Find("tbar").multipatch_applies);
  EXPECT_FALSE(Find("dumbbell").compare_modes);
}

TEST_F(WorkPrecisionScenariosTest, StackMeasuresTheTopBoxAtRest) {
  const Scenario& stack = Find("stack");
  EXPECT_EQ(stack.scene.bodies[stack.body].name, "top");
  EXPECT_DOUBLE_EQ(stack.scene.duration, kBodyScenarioDuration);
  const engine::BodyState end = stack.analytic(stack.scene.duration);
  EXPECT_EQ(end.p_WB, stack.scene.bodies[stack.body].p0);
  EXPECT_EQ(end.v_WB.norm(), 0);
  EXPECT_TRUE(stack.scene.contacts.size() > 3u);  // ground and box–box pairs
}

TEST_F(WorkPrecisionScenariosTest, PushBoxMovesAtThePushersSpeedFromContactOn) {
  const Scenario& push = Find("push_box");
  EXPECT_EQ(push.scene.bodies[push.body].name, "box");
  const engine::Body& box = push.scene.bodies[push.body];
  // the pusher's +x face starts 1 cm short of the box's −x face and moves at 0.1 m/s: contact
  // at t = 0.1 s, then the box at 0.1 m/s (push_box.yaml)
  const double speed = 0.1, contact = 0.01 / speed;
  EXPECT_EQ(push.analytic(contact - 1e-3).p_WB, box.p0);
  EXPECT_EQ(push.analytic(contact - 1e-3).v_WB.norm(), 0);
  const engine::BodyState later = push.analytic(0.6);
  EXPECT_NEAR(later.p_WB.x() - box.p0.x(), speed * (0.6 - contact), kUnitRoundOff);
  EXPECT_NEAR(later.v_WB.x(), speed, kUnitRoundOff);
  EXPECT_FALSE(push.planar_applies);  // body–body contact: the planar model refuses it
}

TEST_F(WorkPrecisionScenariosTest, PyramidIsTenTouchingBoxesMeasuredAgainstRest) {
  const Scenario& pyramid = Find("pyramid");
  ASSERT_EQ(pyramid.scene.bodies.size(), 10u);
  EXPECT_EQ(pyramid.scene.bodies[pyramid.body].name, "top");
  EXPECT_DOUBLE_EQ(pyramid.scene.duration, kManyBodyScenarioDuration);
  EXPECT_TRUE(pyramid.measure_drift);
  EXPECT_EQ(pyramid.drift_projection, Eigen::Matrix3d::Identity());
  // rows 4-3-2-1 of 0.1 m cubes: the top one's CM at 3.5 boxes, and it never moves
  EXPECT_NEAR(pyramid.scene.bodies[pyramid.body].p0.z(), 0.35, kUnitRoundOff);
  const engine::BodyState end = pyramid.analytic(pyramid.scene.duration);
  EXPECT_EQ(end.p_WB, pyramid.scene.bodies[pyramid.body].p0);
  EXPECT_EQ(end.v_WB.norm(), 0);
  EXPECT_FALSE(pyramid.planar_applies);  // body–body contact: the planar model refuses it
}

TEST_F(WorkPrecisionScenariosTest, TrainPushesTheRowFromTheStart) {
  const Scenario& train = Find("train");
  ASSERT_EQ(train.scene.bodies.size(), 7u);  // six boxes and the pusher
  EXPECT_EQ(train.scene.bodies[train.body].name, "c1");
  EXPECT_TRUE(train.scene.bodies[train.pusher].IsKinematic());
  // the pusher touches c1 at t = 0 and the row moves at its 0.1 m/s along +x from then on
  EXPECT_NEAR(train.push_contact_time, 0, kUnitRoundOff);
  EXPECT_NEAR(train.push_direction.x(), 1, kUnitRoundOff);
  EXPECT_NEAR(train.push_force, 0.3 * 6 * kG, kUnitRoundOff);
  const engine::BodyState later = train.analytic(1.0);
  EXPECT_NEAR(later.p_WB.x() - train.scene.bodies[train.body].p0.x(), 0.1, kUnitRoundOff);
  // the drift is the part across the push: x is dropped, y and z kept
  EXPECT_NEAR((train.drift_projection * Eigen::Vector3d(1, 2, 3)).norm(), std::sqrt(13.0),
              kUnitRoundOff);
}

TEST_F(WorkPrecisionScenariosTest, PegInHoleMeasuresThePegOverItsScenesWholeRun) {
  const Scenario& peg = Find("peg_in_hole");
  const engine::Body& body = peg.scene.bodies[peg.body];
  EXPECT_EQ(body.name, "peg");
  // the scene file's own duration, whichever version of the scene it is
  const engine::Scene file =
      engine::LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/peg_in_hole.yaml").scene;
  EXPECT_EQ(peg.scene.duration, file.duration);
  EXPECT_TRUE(peg.has_reference);
  EXPECT_FALSE(static_cast<bool>(peg.analytic));  // converged
  // the peg touches the block's parts, which the models and the peers all get; the planar and
  // multi-patch models refuse contacts between bodies
  EXPECT_TRUE(std::any_of(peg.scene.contacts.begin(), peg.scene.contacts.end(),
                          [](const engine::ContactPair& pair) { return pair.part >= 0; }));
  EXPECT_FALSE(peg.planar_applies);
  EXPECT_FALSE(peg.multipatch_applies);
  // the orientation error's lever is the peg's farthest point from its CM: for a box at its CM,
  // half its bounding box's diagonal
  Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = -low;
  for (const Eigen::Vector3d& v : body.hull->Tessellate().vertices) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  EXPECT_NEAR(peg.length, (high - low).norm() / 2, kUnitRoundOff);
}

TEST_F(WorkPrecisionScenariosTest, DominoesRunToRestWithoutAReference) {
  const Scenario& dominoes = Find("dominoes");
  ASSERT_EQ(dominoes.scene.bodies.size(), 9u);
  EXPECT_EQ(dominoes.scene.bodies[dominoes.body].name, "d9");
  // the scene stops at 0.7 s, during the cascade; the scenario runs on past the landings
  EXPECT_DOUBLE_EQ(dominoes.scene.duration, kDominoesDuration);
  EXPECT_FALSE(dominoes.has_reference);
  EXPECT_FALSE(static_cast<bool>(dominoes.analytic));
  EXPECT_TRUE(dominoes.measure_drift);
  EXPECT_DOUBLE_EQ(dominoes.drift_from, kDominoesSettleTime);
  EXPECT_LT(dominoes.drift_from, dominoes.scene.duration);
  EXPECT_EQ(dominoes.only_steps, kPileSteps);
}

TEST_F(WorkPrecisionScenariosTest, ClutterBinsDropTheirBoxesWithoutAReference) {
  for (const auto& [name, boxes] : {std::pair("clutter", 24u), std::pair("clutter96", 96u)}) {
    const Scenario& clutter = Find(name);
    EXPECT_EQ(clutter.scene.bodies.size(), boxes) << name;
    EXPECT_FALSE(clutter.has_reference) << name;
    EXPECT_FALSE(clutter.compare_modes) << name;
    EXPECT_TRUE(clutter.measure_drift) << name;
    EXPECT_DOUBLE_EQ(clutter.drift_from, kClutterSettleTime) << name;
    EXPECT_DOUBLE_EQ(clutter.scene.duration, 2 * kClutterSettleTime) << name;
    EXPECT_FALSE(clutter.planar_applies) << name;  // body–body contact
    EXPECT_EQ(clutter.only_steps, kPileSteps) << name;
  }
}

TEST(SceneScenarioTest, NamesTheFileAndTheMissingBody) {
  EXPECT_THROW(SceneScenario(std::string(ECPSIM_SOURCE_DIR) + "/scenes", "x", "stack.yaml",
                             "nobody", 1, 0.1, "x"),
               InputError);
  try {
    SceneScenario(std::string(ECPSIM_SOURCE_DIR) + "/scenes", "x", "stack.yaml", "nobody", 1, 0.1,
                  "x");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stack.yaml: no body 'nobody'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ecpsim::evaluation
