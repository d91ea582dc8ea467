// ValidateScene on scenes built in code: every message names the key path, the body or obstacle
// by name, the value and what was expected, without any file.

#include "engine/scene_io/scene_validation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_limits.h"

namespace ecpsim::engine {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// a 0.5 × 0.5 × 0.1 m, 15 kg box resting on the ground z = 0 (its CM at z = 0.05 m)
Scene RestingBox() {
  Body box = MakeBoxBody(Eigen::Vector3d(0.5, 0.5, 0.1), 15, "crate");
  box.p0 = Eigen::Vector3d(0, 0, 0.05);
  return MakeGroundScene({box}, 0.01, Friction{});
}

// the error `validate` throws for `scene`; fails the test when it throws none
template <typename S>
SceneError ErrorOf(const S& scene, void (*validate)(const S&)) {
  try {
    validate(scene);
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "the scene was accepted";
  return SceneError({"(none)"}, "", "");
}
SceneError ErrorOf(const Scene& scene) { return ErrorOf(scene, &ValidateScene); }
SceneError ErrorOf(const LoadedScene& loaded) { return ErrorOf(loaded, &ValidateLoadedScene); }

TEST(SceneValidationTest, ABoxRestingOnTheGroundPasses) {
  EXPECT_NO_THROW(ValidateScene(RestingBox()));
}

TEST(SceneValidationTest, StepCountAboveTheLimitNamesHAndTheCount) {
  Scene scene = RestingBox();
  scene.h = 1e-16;
  const SceneError e = ErrorOf(scene);
  EXPECT_THAT(e.keys(), ElementsAre("h", "duration"));
  EXPECT_THAT(e.what(), HasSubstr("h = 1e-16: expected at most 4503599627370496 steps per run, "
                                  "here duration / h = 1 / 1e-16 = 1e+16 steps"));
  // exactly the limit passes
  scene.h = 1.0 / kMaxSteps;
  EXPECT_NO_THROW(ValidateScene(scene));
}

TEST(SceneValidationTest, StepLongerThanTheDurationOrNotFiniteIsRejected) {
  Scene scene = RestingBox();
  scene.h = 2;
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("h = 2: expected a time step h <= duration = 1 s"));
  scene.h = std::nan("");
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("h = nan: expected a finite time step > 0 s"));
  scene.h = 0.01;
  scene.duration = 1e200;
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("duration = 1e+200: expected a finite duration"));
}

TEST(SceneValidationTest, InitialPenetrationNamesBodyObstacleDepthAndTheKeyToAllowIt) {
  Scene scene = RestingBox();
  scene.bodies[0].p0.z() = -0.35;  // its bottom 0.4 m into the ground
  const SceneError e = ErrorOf(scene);
  EXPECT_EQ(e.keys().front(), "bodies[0].position");
  EXPECT_THAT(e.what(),
              AllOf(HasSubstr("bodies[0].position = [0, 0, -0.35]: expected an initial pose of "
                              "body \"crate\" whose mesh stays out of obstacle \"ground\": a "
                              "vertex is 0.4 m inside"),
                    HasSubstr("bodies[0].allow_initial_penetration: true")));
  scene.bodies[0].allow_initial_penetration = true;
  EXPECT_NO_THROW(ValidateScene(scene));
}

TEST(SceneValidationTest, BodiesOfAPairOverlappingAtTheStartNameBothAndTheWaysOut) {
  // a second crate resting on the first, 1 cm too low
  Scene scene = RestingBox();
  Body top = MakeBoxBody(Eigen::Vector3d(0.5, 0.5, 0.1), 15, "lid");
  top.p0 = Eigen::Vector3d(0, 0, 0.14);
  scene.bodies.push_back(top);
  AddBodyPairs(scene);
  const SceneError e = ErrorOf(scene);
  EXPECT_EQ(e.keys().front(), "bodies[0].position");
  EXPECT_THAT(e.what(),
              AllOf(HasSubstr("expected an initial pose of body \"crate\" apart from "
                              "body \"lid\": they overlap by 0.01 m"),
                    HasSubstr("exclude: true"), HasSubstr("allow_initial_penetration: true")));
  scene.bodies[1].allow_initial_penetration = true;
  EXPECT_NO_THROW(ValidateScene(scene));
  // resting exactly on it passes; an excluded pair (no contact pair) may overlap
  scene.bodies[1].allow_initial_penetration = false;
  scene.bodies[1].p0.z() = 0.15;
  EXPECT_NO_THROW(ValidateScene(scene));
  scene.bodies[1].p0.z() = 0.14;
  scene.contacts.pop_back();
  EXPECT_NO_THROW(ValidateScene(scene));
}

TEST(SceneValidationTest, InitialPenetrationToleranceIsRelativeToTheBodySize) {
  // the same overlap relative to the size passes or fails alike at any scale
  for (const double scale : {1e-3, 1.0, 1e3}) {
    Body box = MakeBoxBody(scale * Eigen::Vector3d(0.5, 0.5, 0.1), 15, "crate");
    const double tolerance = kInitialPenetrationTolerance * MeshAcross(box.mesh);
    box.p0 = Eigen::Vector3d(0, 0, scale * 0.05 - 0.5 * tolerance);
    Scene scene = MakeGroundScene({box}, 0.01, Friction{});
    EXPECT_NO_THROW(ValidateScene(scene)) << "scale " << scale;
    scene.bodies[0].p0.z() = scale * 0.05 - 2 * tolerance;
    EXPECT_THROW(ValidateScene(scene), SceneError) << "scale " << scale;
  }
}

TEST(SceneValidationTest, NonFiniteOrOutOfRangeMassPropertiesNameTheBody) {
  Scene scene = RestingBox();
  scene.bodies[0].mass = std::numeric_limits<double>::infinity();
  SceneError e = ErrorOf(scene);
  EXPECT_THAT(e.keys(), ElementsAre("bodies[0].mass", "bodies[0].density", "bodies[0]"));
  EXPECT_THAT(e.what(), HasSubstr("bodies[0].mass = inf: expected a mass of body \"crate\""));

  // 1e-149 kg in the box: I_xx = m (0.5² + 0.1²) / 12 = 2.17e-151 kg·m², below the range
  scene = RestingBox();
  scene.bodies[0] = MakeBoxBody(Eigen::Vector3d(0.5, 0.5, 0.1), 1e-149, "crate");
  scene.bodies[0].p0.z() = 0.05;
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("expected principal moments of body \"crate\" that are each a principal "
                        "moment of inertia in [1e-150, 1e+150] kg·m²; it is 2.17e-151 kg·m²"));

  scene = RestingBox();
  scene.bodies[0].inertia(0, 0) = 10;  // breaks I_xx ≤ I_yy + I_zz
  e = ErrorOf(scene);
  EXPECT_EQ(e.keys().front(), "bodies[0].inertia");
  EXPECT_THAT(e.what(), HasSubstr("each principal moment <= the sum of the other two"));

  scene = RestingBox();
  scene.bodies[0].inertia(0, 1) = 0.1;  // not symmetric
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("that is symmetric, positive definite"));
}

TEST(SceneValidationTest, PoseAndVelocitiesMustBeFiniteAndNearTheOrigin) {
  Scene scene = RestingBox();
  scene.bodies[0].q0 = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("bodies[0].quaternion = [0, 0, 0, 0]: expected a non-zero, finite "
                        "orientation quaternion [w, x, y, z] of body \"crate\""));

  scene = RestingBox();
  scene.bodies[0].v0.x() = std::nan("");
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("bodies[0].velocity = [nan, 0, 0]: expected a "
                                               "velocity of body \"crate\" in m/s"));

  // 1e6 sizes of the 0.71 m box from the origin is the limit
  scene = RestingBox();
  scene.bodies[0].p0.x() = 1e7;
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("expected body \"crate\" within 1e+06 × its size 0.714 m of the origin"));
}

TEST(SceneValidationTest, FrictionOfAContactNamesBodyAndObstacle) {
  Scene scene = RestingBox();
  scene.contacts[0].friction.mu = -0.2;
  const SceneError e = ErrorOf(scene);
  EXPECT_THAT(e.keys(), ElementsAre("bodies[0].friction.mu", "obstacles[0].friction.mu",
                                    "contacts[0].friction.mu"));
  EXPECT_THAT(e.what(), HasSubstr("expected a friction coefficient >= 0 (within 1e+150) for the "
                                  "contact of body \"crate\" with obstacle \"ground\""));
  scene = RestingBox();
  scene.obstacles[0].friction.e_r = 0;
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("obstacles[0].friction.e_r = 0: expected a torsional ellipsoid "
                        "semi-axis > 0 m, or `patch`, for obstacle \"ground\""));
  // `e_r: patch` leaves the number unused: it is not checked
  scene.obstacles[0].friction.e_r_patch = true;
  scene.contacts[0].friction.e_r_patch = true;
  scene.contacts[0].friction.e_r = 0;
  EXPECT_NO_THROW(ValidateScene(scene));
}

TEST(SceneValidationTest, NamesAndReferencesMustBeValid) {
  Scene scene = RestingBox();
  scene.bodies.push_back(scene.bodies[0]);
  scene.bodies[1].p0.x() = 2;
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("bodies[1].name = \"crate\": expected a name no other body has"));
  scene = RestingBox();
  scene.bodies.clear();
  scene.contacts.clear();
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("bodies = []: expected a list of at least one body"));
  scene = RestingBox();
  scene.obstacles[0].name = "the ground";
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("obstacles[0].name = \"the ground\": expected a "
                                               "name of letters, digits"));
  scene = RestingBox();
  scene.impulses.push_back(Impulse{3, 0.5});
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("impulses[0].body = 3: expected a body index 0..0"));
}

TEST(SceneValidationTest, LoadsImpulsesAndSettingsHaveTheirRanges) {
  Scene scene = RestingBox();
  Load load;
  load.start = 2;
  load.end = 1;
  scene.loads.push_back(load);
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("loads[0].end = 1: expected an end time (s) > "
                                               "start = 2"));
  scene = RestingBox();
  scene.impulses.push_back(Impulse{0, -1});
  EXPECT_THAT(ErrorOf(scene).what(), HasSubstr("impulses[0].time = -1: expected a finite time "
                                               ">= 0 s"));
  scene = RestingBox();
  scene.solver.max_iterations = kMaxSolverIterations + 1;
  EXPECT_THAT(ErrorOf(scene).what(),
              HasSubstr("solver.max_iterations = 10001: expected an integer in [1, 10000]"));
}

TEST(SceneValidationTest, OutputSettingsHaveTheirRanges) {
  LoadedScene loaded{RestingBox(), {}, {}};
  EXPECT_NO_THROW(ValidateLoadedScene(loaded));
  loaded.output.width = 8193;
  EXPECT_THAT(ErrorOf(loaded).what(), HasSubstr("output.width = 8193: expected an integer in "
                                                "[16, 8192]"));
  loaded.output = OutputSettings{};
  loaded.output.every = 0;
  EXPECT_THAT(ErrorOf(loaded).what(), HasSubstr("output.every = 0: expected an integer >= 1"));
  loaded.output = OutputSettings{};
  loaded.output.camera_target = loaded.output.camera_position;
  EXPECT_THAT(ErrorOf(loaded).what(), HasSubstr("expected a camera position different from its "
                                                "target"));
}

TEST(SceneValidationTest, OutputSettingsAreCheckedAfterTheSolverAndBeforeTheInitialOverlap) {
  // a file's first problem is the same as when the output block was part of the Scene
  LoadedScene loaded{RestingBox(), {}, {}};
  loaded.output.fps = 0;
  loaded.scene.bodies[0].p0.z() = -0.2;  // 0.25 m inside the ground
  EXPECT_EQ(ErrorOf(loaded).keys().at(0), "output.fps");
  loaded.scene.solver.window_rings = -1;
  EXPECT_EQ(ErrorOf(loaded).keys().at(0), "solver.window_rings");
  loaded.scene.solver.window_rings = 1;
  loaded.output.fps = 30;
  EXPECT_EQ(ErrorOf(loaded).keys().at(0), "bodies[0].position");
}

}  // namespace
}  // namespace ecpsim::engine
