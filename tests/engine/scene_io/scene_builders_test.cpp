// Scenes built in code (engine/scene_io/scene_builders.h): MakeGroundScene is a route into a
// Scene, so it returns only what ValidateScene accepts, named with the Scene's keys.

#include "engine/scene_io/scene_builders.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/scene_io/scene_validation.h"

namespace ecpsim::engine {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// a 0.2 m cube resting on the ground (its CM at z = 0.1 m)
Body RestingCube(double mass) {
  Body cube = MakeBoxBody(Eigen::Vector3d::Constant(0.2), mass, "cube");
  cube.p0 = Eigen::Vector3d(0, 0, 0.1);
  return cube;
}

TEST(MakeGroundSceneTest, ACubeOnTheGroundTouchesItWithTheFrictionGiven) {
  const Friction friction{0.4, 1, 1, 0.05};
  const Scene scene = MakeGroundScene({RestingCube(2)}, 0.005, friction);
  EXPECT_EQ(scene.source, "code");
  EXPECT_EQ(scene.h, 0.005);
  EXPECT_EQ(scene.duration, 1);
  ASSERT_EQ(scene.obstacles.size(), 1u);
  EXPECT_EQ(scene.obstacles[0].shape->Value(0, Eigen::Vector3d(0, 0, -0.5)), -0.5);
  ASSERT_EQ(scene.contacts.size(), 1u);
  EXPECT_EQ(scene.contacts[0].body, 0);
  EXPECT_EQ(scene.contacts[0].obstacle, 0);
  EXPECT_EQ(scene.contacts[0].friction.mu, 0.4);
}

TEST(MakeGroundSceneTest, RejectsAZeroTimeStepNamingH) {
  EXPECT_THAT([] { MakeGroundScene({RestingCube(2)}, 0, Friction{}); },
              ThrowsMessage<SceneError>(
                  HasSubstr("h = 0: expected a finite time step > 0 s: a time in [1e-150, "
                            "1e+150] s")));
}

TEST(MakeGroundSceneTest, RejectsANegativeMassNamingTheBody) {
  EXPECT_THAT([] { MakeGroundScene({RestingCube(-2)}, 0.01, Friction{}); },
              ThrowsMessage<SceneError>(
                  AllOf(HasSubstr("bodies[0].mass = -2: expected a mass of body \"cube\" that is a "
                                  "mass in [1e-150, 1e+150] kg"),
                        HasSubstr("it is -2 kg"))));
}

TEST(MakeGroundSceneTest, RejectsANegativeFrictionCoefficientNamingTheContact) {
  EXPECT_THAT(
      [] {
        MakeGroundScene({RestingCube(2)}, 0.01, Friction{-0.1, 1, 1, 0.1});
      },
      ThrowsMessage<SceneError>(
          HasSubstr("obstacles[0].friction.mu = -0.1: expected a friction coefficient >= 0 (within "
                    "1e+150) for obstacle \"ground\"")));
}

TEST(MakeGroundSceneTest, RejectsABodyStartingInsideTheGround) {
  // at the origin, a cube is half inside z ≤ 0
  Body sunk = RestingCube(2);
  sunk.p0.setZero();
  EXPECT_THAT([&] { MakeGroundScene({sunk}, 0.01, Friction{}); },
              ThrowsMessage<SceneError>(HasSubstr(
                  "bodies[0].position = [0, 0, 0]: expected an initial pose of body \"cube\" whose "
                  "mesh stays out of obstacle \"ground\": a vertex is 0.1 m inside")));
  // unless the overlap is asked for
  sunk.allow_initial_penetration = true;
  EXPECT_NO_THROW(MakeGroundScene({sunk}, 0.01, Friction{}));
}

}  // namespace
}  // namespace ecpsim::engine
