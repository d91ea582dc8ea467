#include "engine/models/planar_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/time_step.h"
#include "geometry/paper_bodies.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using ::testing::HasSubstr;

// m/s, rad/s or m: the paper's bar on the hull-ECP and planar models' difference
constexpr double kModelAgreement = 1e-8;
// m: the hull model holds the desk's height to the scenes' solver tolerance of O(1) lengths
constexpr double kSolverTolerance = 1e-12;

Scene PaperDesk(ContactModel model) { return testing::PaperDeskScene(model); }

TEST(PlanarModelTest, AgreesWithTheHullModelOnThePaperDesk) {
  // the paper's claim: |Δv_x|, |Δω_z| < 1e-8 between the hull-ECP and planar sliding models
  const Scene hull_scene = PaperDesk(ContactModel::kHull);
  const Scene planar_scene = PaperDesk(ContactModel::kPlanar);
  State hull = InitialState(hull_scene), planar = InitialState(planar_scene);
  double max_dv = 0, max_dw = 0;
  for (int i = 0; i < 400; ++i) {
    ASSERT_TRUE(Step(hull_scene, hull).converged);
    ASSERT_TRUE(Step(planar_scene, planar).converged);
    max_dv = std::max(max_dv, std::abs(hull.bodies[0].v_WB.x() - planar.bodies[0].v_WB.x()));
    max_dw = std::max(max_dw, std::abs(hull.bodies[0].w_WB.z() - planar.bodies[0].w_WB.z()));
    // the hull model keeps the desk flat and at its height by itself
    ASSERT_NEAR(hull.bodies[0].p_WB.z(), 0.45, kSolverTolerance);
    // both ECPs coincide
    ASSERT_LE((hull.contacts[0].a1 - planar.contacts[0].a1).norm(), kModelAgreement);
  }
  EXPECT_LT(max_dv, kModelAgreement);
  EXPECT_LT(max_dw, kModelAgreement);
  // the desk really moved and turned (not a trivial agreement at rest)
  EXPECT_GT(hull.bodies[0].p_WB.head<2>().norm(), 0.5);
}

TEST(PlanarModelTest, SaysSoWhenTheBodyWouldTip) {
  // a tall narrow box pushed high: the statics say it tips (TipOrSlideTest), so the planar
  // model's ECP leaves the support face and the run must stop rather than slide on
  Body box = testing::MakeBoxBody(Vector3d(0.1, 0.3, 0.6), 3);
  box.p0 = Vector3d(0, 0, 0.3);
  Scene scene = testing::MakeGroundScene({box});
  scene.model = ContactModel::kPlanar;
  Load push;
  push.x = TimeFunction(4.0);
  push.at_point = true;
  push.point_B = Vector3d(-0.05, 0, 0.2);
  scene.loads.push_back(push);
  State state = InitialState(scene);
  EXPECT_THAT([&] { Step(scene, state); },
              ::testing::ThrowsMessage<ModelInvalid>(HasSubstr("left the support face")));
  EXPECT_EQ(state.t, 0.0) << "the state stays at the last valid step";
}

TEST(PlanarModelTest, RejectsABodyThatIsNotFlat) {
  Body box = testing::MakeBoxBody(Vector3d(0.4, 0.3, 0.2), 3);
  box.q0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vector3d::UnitX()));
  box.p0 = Vector3d(0, 0, 0.5);
  Scene scene = testing::MakeGroundScene({box});
  scene.model = ContactModel::kPlanar;
  State state = InitialState(scene);
  EXPECT_THAT([&] { Step(scene, state); },
              ::testing::ThrowsMessage<ModelInvalid>(HasSubstr("not flat")));
}

}  // namespace
}  // namespace ecpsim::engine
