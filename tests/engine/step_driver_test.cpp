#include "engine/step_driver.h"

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/islands.h"
#include "engine/models/hull_model.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/time_step.h"
#include "geometry/convex_separation.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::MakeBoxBody;
using testing::MakeGroundScene;

// m: one rounding of a coordinate |x| ≈ 1 (ε = 2.2e-16, rounded up)
constexpr double kRoundingOfOne = 2.3e-16;

// A model that moves each body by h along x and solves only spans of at most `largest_h` (for
// the body named "stubborn"; every other body at any h) among those that end after
// `hard_from` (any span that ends before it solves): the driver's splitting is what is under
// test, with the outcome known in advance.
class SubstepModel final : public ContactModelStepper {
 public:
  explicit SubstepModel(const Scene& scene, double largest_h, double hard_from = -INFINITY)
      : scene_(scene), largest_h_(largest_h), hard_from_(hard_from) {}
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort) const override {
    AdvanceResult result;
    ++calls;
    result.iterations = 1;
    const bool stubborn = scene_.bodies[island.bodies[0]].name == "stubborn";
    if (stubborn && h > largest_h_ && t + h > hard_from_) {
      result.residual = 0.5;
      result.retries = 1;
      result.tried.push_back({"test", h, "refused"});
      state.bodies[0].p_WB.setConstant(NAN);  // a failed attempt's state must never be committed
      return result;
    }
    if (stubborn) solved_spans.push_back({t, h});
    for (BodyState& b : state.bodies) b.p_WB.x() += h;
    result.residual = h;
    result.solved = true;
    return result;
  }
  mutable int calls = 0;
  mutable std::vector<std::pair<double, double>> solved_spans;  // the stubborn body's (t, h)

 private:
  const Scene& scene_;
  double largest_h_, hard_from_;
};

// the one stepper `model` for every thread (the tests' models are used on one)
WithModel Using(const ContactModelStepper& model) {
  return [&model](StepWorkspace&, const std::function<void(const ContactModelStepper&)>& use) {
    use(model);
  };
}

Scene TwoBoxes() {
  Body a = MakeBoxBody(Vector3d(0.1, 0.1, 0.1), 1);
  a.name = "easy";
  a.p0 = Vector3d(0, 0, 1);
  Body b = a;
  b.name = "stubborn";
  b.p0 = Vector3d(1, 0, 1);
  return MakeGroundScene({a, b});
}

TEST(FormIslandsTest, EveryBodyIsAnIslandWithItsObstacleContacts) {
  const Scene scene = TwoBoxes();
  const std::vector<Island> islands = FormIslands(scene, InitialState(scene));
  ASSERT_EQ(islands.size(), 2u);
  for (int b = 0; b < 2; ++b) {
    EXPECT_EQ(islands[b].bodies, std::vector<int>{b});
    ASSERT_EQ(islands[b].contacts.size(), 1u);
    EXPECT_EQ(scene.contacts[islands[b].contacts[0]].body, b);
  }
}

TEST(StepIslandsTest, AnIslandThatFailsAtHIsSplitUntilItsSpansSolve) {
  const Scene scene = TwoBoxes();
  State state = InitialState(scene);
  StepWorkspace workspace;
  // solvable at h/4 only: h fails, then each half fails and is split into quarters that solve
  const SubstepModel model(scene, scene.h / 4);
  const StepReport report = StepIslands(scene, state, Using(model), workspace);
  EXPECT_EQ(report.substeps, 4);
  EXPECT_EQ(report.retries, 3);
  EXPECT_EQ(model.calls, 1 + 1 + (1 + 2) + (1 + 2));
  // each body moved by h (the stubborn one in four roundings of x + h/4: a few ulps of 1), and
  // the failed attempts' NaN never reached the state
  constexpr double kFourRoundings = 4 * kRoundingOfOne;
  EXPECT_EQ(state.bodies[0].p_WB.x(), scene.h);
  EXPECT_NEAR(state.bodies[1].p_WB.x(), 1 + scene.h, kFourRoundings);
  EXPECT_EQ(state.steps, 1);
  // the largest residual of any island's accepted sub-steps (the easy body's, solved at h)
  EXPECT_EQ(report.residual, scene.h);
}

TEST(StepIslandsTest, ASolvedSpanIsKeptAndOnlyTheHalfThatFailedIsSplit) {
  const Scene scene = TwoBoxes();
  State state = InitialState(scene);
  StepWorkspace workspace;
  // hard only in the step's second half: the first half solves at h/2 once and is kept, the
  // second is split into quarters
  const SubstepModel model(scene, scene.h / 4, scene.h / 2);
  const StepReport report = StepIslands(scene, state, Using(model), workspace);
  const double h = scene.h;
  const std::vector<std::pair<double, double>> spans = {
      {0, h / 2}, {h / 2, h / 4}, {h / 2 + h / 4, h / 4}};
  EXPECT_EQ(model.solved_spans, spans);
  EXPECT_EQ(report.substeps, 4);
  EXPECT_EQ(model.calls, 1 + 1 + 1 + (1 + 2));
  EXPECT_NEAR(state.bodies[1].p_WB.x(), 1 + scene.h, 3 * kRoundingOfOne);
}

TEST(StepIslandsTest, AnIslandThatNeverSolvesNamesTimeBodyAndWhatWasTriedAndLeavesTheState) {
  Scene scene = TwoBoxes();
  scene.model = ContactModel::kPlanar;  // the failure names a model other than the hull's
  State state = InitialState(scene);
  StepWorkspace workspace;
  const State before = state;
  const SubstepModel model(scene, scene.h / 100);  // below the finest split, h/16
  EXPECT_THAT([&] { StepIslands(scene, state, Using(model), workspace); },
              ::testing::ThrowsMessage<SolverFailure>(
                  AllOf(HasSubstr("planar model: solver failed at t = 0 s on body 'stubborn': "
                                  "residual 0.5 > tolerance 1e-12"),
                        HasSubstr("tried test (h = 0.01 s): refused; test (h = 0.005 s): "
                                  "refused; test (h = 0.0025 s): refused; test (h = 0.00125 s): "
                                  "refused; test (h = 0.000625 s): refused"))));
  // the same as a record: the step and each first half down to h/16 refused
  try {
    StepIslands(scene, state, Using(model), workspace);
    ADD_FAILURE() << "no SolverFailure";
  } catch (const SolverFailure& failure) {
    const StepFailure* record = failure.step_failure();
    ASSERT_NE(record, nullptr);
    EXPECT_EQ(record->model, "planar");
    EXPECT_EQ(record->bodies, std::vector<std::string>{"stubborn"});
    EXPECT_EQ(record->residual, 0.5);
    ASSERT_EQ(record->tried.size(), 5u);
    EXPECT_EQ(record->tried[4].h, scene.h / 16);
  }
  EXPECT_EQ(state.steps, 0);
  for (size_t b = 0; b < state.bodies.size(); ++b)
    EXPECT_EQ(state.bodies[b].p_WB, before.bodies[b].p_WB);
}

// The SubstepModel whose Advance never solves the stubborn body, with a last resort that solves
// it at spans of at most `last_resort_h`; it records which effort each attempt had.
class LastResortModel final : public ContactModelStepper {
 public:
  LastResortModel(const Scene& scene, double last_resort_h)
      : advance_(scene, 0), last_resort_(scene, last_resort_h) {}
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override {
    if (effort == Effort::kLastResort) {
      // a span is given the last resort only after its usual effort failed
      EXPECT_FALSE(efforts.empty() || efforts.back() != 'u' || last_h != h)
          << "the last resort before the usual effort at t = " << t << ", h = " << h;
      efforts += 'L';
      return last_resort_.Advance(island, t, h, state, effort);
    }
    efforts += 'u';
    last_h = h;
    return advance_.Advance(island, t, h, state, effort);
  }
  bool HasLastResort() const override { return true; }
  SubstepModel advance_, last_resort_;
  mutable std::string efforts;  // per attempt: 'u' usual, 'L' last resort
  mutable double last_h = 0;    // the last usual attempt's span
};

TEST(StepIslandsTest, TheLastResortIsGivenOnlyToSpansThatSplittingDidNotSolve) {
  const Scene scene = TwoBoxes();
  State state = InitialState(scene);
  StepWorkspace workspace;
  // the usual effort never solves the stubborn body: every span from h down to h/16 fails with
  // it and is split (1 + 2 + 4 + 8 spans), and each of the 16 spans of h/16 fails with it too
  // and is solved by the last resort; the easy body is solved by Advance at h
  const LastResortModel model(scene, scene.h / 2);
  const StepReport report = StepIslands(scene, state, Using(model), workspace);
  EXPECT_EQ(model.advance_.calls, 1 + (1 + 2 + 4 + 8) + 16);
  EXPECT_EQ(model.last_resort_.calls, 16);
  EXPECT_EQ(report.substeps, 16);
  // sixteen roundings of x + h/16
  EXPECT_NEAR(state.bodies[1].p_WB.x(), 1 + scene.h, 16 * kRoundingOfOne);
  EXPECT_EQ(state.steps, 1);
}

TEST(StepIslandsTest, AModelWithoutALastResortFailsAfterTheSplits) {
  const Scene scene = TwoBoxes();
  State state = InitialState(scene);
  StepWorkspace workspace;
  const SubstepModel model(scene, scene.h / 100);
  EXPECT_THROW(StepIslands(scene, state, Using(model), workspace), SolverFailure);
  // the easy body, then the step and each first half down to h/16 for the stubborn one
  EXPECT_EQ(model.calls, 1 + 5);
}

TEST(StepIslandsTest, TheHullModelThroughTheDriverIsTheStep) {
  // the driver with the hull model is what Step runs: bit-identical states
  Body box = MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 2);
  box.p0 = Vector3d(0, 0, 0.2);
  box.v0 = Vector3d(0.4, 0.1, 0);
  box.w0 = Vector3d(0.5, 1, 2);
  Scene scene = MakeGroundScene({box});
  scene.model = ContactModel::kHull;
  State a = InitialState(scene), b = a;
  StepWorkspace workspace;
  const HullModel hull(scene, workspace);
  for (int i = 0; i < 40; ++i) {
    StepIslands(scene, a, Using(hull), workspace);
    Step(scene, b);
    ASSERT_EQ(a.bodies[0].p_WB, b.bodies[0].p_WB);
    ASSERT_EQ(a.bodies[0].Q_WB.coeffs(), b.bodies[0].Q_WB.coeffs());
  }
}

// m/m: how deep two boxes the step left touching may overlap, relative to their size: the
// MNCP's non-penetration holds to its tolerance (1e-12), far below this
constexpr double kTouchingOverlapRel = 1e-10;
constexpr double kRowBoxSize = 0.1;  // m

// Three cubes a, b, c in a row along x on the ground, every pair a contact pair: a touching b
// and moving toward it at `speed`, c `gap` beyond b. b and c at rest cannot close a gap of more
// than 2 h² |g| (2 mm at h = 0.01 s) by themselves, so the islands leave b–c out of the step
Scene RowOfBoxes(double gap, double speed) {
  std::vector<Body> boxes;
  const double xs[] = {0, kRowBoxSize, 2 * kRowBoxSize + gap};
  for (int i = 0; i < 3; ++i) {
    Body box = MakeBoxBody(Vector3d::Constant(kRowBoxSize), 1, std::string(1, 'a' + i));
    box.p0 = Vector3d(xs[i], 0, kRowBoxSize / 2);
    boxes.push_back(box);
  }
  boxes[0].v0 = Vector3d(speed, 0, 0);
  Scene scene = MakeGroundScene(boxes);
  AddBodyPairs(scene);
  return scene;
}

// the contact pair between b and c in RowOfBoxes
int PairBC(const Scene& scene) {
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (pair.WithBody() && pair.body + pair.other_body == 3) return static_cast<int>(k);
  }
  return -1;
}

TEST(StepIslandsTest, APairLeftOutAsApartThatAStrikeClosesIsSolvedInTheStep) {
  // a strikes b at 4 m/s and gives it 2 m/s, 2 cm in the step: b–c, 1 cm apart and left out, does
  // not end the step apart, and the driver solves the step again with the pair in
  const Scene scene = RowOfBoxes(0.01, 4);
  State state = InitialState(scene);
  const int b_c = PairBC(scene);
  IslandScratch scratch;
  std::vector<Island> islands;
  FormIslandsInto(scene, state, scratch, islands);
  ASSERT_THAT(scratch.apart, ::testing::Contains(b_c));

  Step(scene, state);
  EXPECT_GT(state.contacts[b_c].p_n, 0) << "b pushes c";
  EXPECT_GT(state.bodies[2].v_WB.x(), 0);
  const double overlap =
      geometry::PenetrationDepth(*scene.bodies[1].hull, PoseOf(state.bodies[1]),
                                 *scene.bodies[2].hull, PoseOf(state.bodies[2]), kRowBoxSize);
  EXPECT_LE(overlap, kTouchingOverlapRel * kRowBoxSize);
}

TEST(StepIslandsTest, APairLeftOutAsApartThatEndsApartReportsNoImpulse) {
  // a at 2 m/s takes b 1 cm, c 5 cm beyond b stays untouched
  const Scene scene = RowOfBoxes(0.05, 2);
  State state = InitialState(scene);
  Step(scene, state);
  EXPECT_GT(state.bodies[1].v_WB.x(), 0) << "a strikes b";
  EXPECT_EQ(state.bodies[2].v_WB, Vector3d::Zero());
  const ContactState& b_c = state.contacts[PairBC(scene)];
  EXPECT_EQ(b_c.p_n, 0);
  EXPECT_TRUE(b_c.warm_start.empty());
}

}  // namespace
}  // namespace ecpsim::engine
