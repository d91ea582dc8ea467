#include "engine/scene_io/scene_yaml.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// values typed in the YAML or a few flops from them: a few ulps of O(1) numbers
constexpr double kTight = 1e-12;

// A unit cube [0, 1]³ as OBJ, so that its centre of mass (0.5, 0.5, 0.5) is off the file origin.
constexpr const char* kCubeObj = R"obj(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
)obj";

class SceneYamlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / fmt::format("ecpsim_scene_yaml_{}_{}", getpid(), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "meshes");
    Write("meshes/cube.obj", kCubeObj);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }

  // writes `yaml` as scene.yaml and loads it
  LoadedScene LoadFile(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
    return LoadScene(Write("scene.yaml", yaml), overrides);
  }
  // the physics of LoadFile
  Scene LoadText(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
    return LoadFile(yaml, overrides).scene;
  }

  std::string ScenePath() const { return (dir_ / "scene.yaml").string(); }

  fs::path dir_;
};

// ---- a complete scene ------------------------------------------------------------------------

constexpr const char* kCompleteScene = R"yaml(gravity: [0, 0, -9.81]
h: 0.005
duration: 2
ground:
  friction: {mu: 0.3, e_t: 1, e_o: 0.8, e_r: 0.05}
obstacles:
  - name: step
    box: {size: [1, 2, 0.2], position: [3, 0, 0.1], rpy: [0, 0, 90]}
  - name: ramp
    plane: {normal: [0, 3, 4], offset: -1}
bodies:
  - name: crate
    shape: {box: {size: [0.5, 0.4, 0.1]}}
    mass: 15
    position: [0, 0, 0.05]
    velocity: [0.5, 0, 0]
    angular_velocity: [0, 0, 1.5]
    friction: {mu: 0.1}
  - name: cube
    mesh: meshes/cube.obj
    scale: 0.5
    density: 800
    rpy: [90, 0, 0]
    position: [1, 2, 3]
  - name: ball
    shape: {sphere: {radius: 0.2}}
    mass: 2
    inertia: [0.1, 0.2, 0.25]
    quaternion: [0, 0, 0, 2]
    position: [0, 0, 1]
loads:
  - body: crate
    force: ["22.5*sin(2*pi*t)+22.5", 0, 1]
    start: 0.5
    end: 1.5
  - body: 1
    force: [0, 0, 10]
    at: [0.5, 0.25, 0.25]
  - body: ball
    torque: [0, 0, "2.1*cos(2*pi*t)"]
impulses:
  - body: cube
    time: 0.75
    linear: [0, 1, 0]
    angular: [0, 0, 0.5]
solver: {tolerance: 1e-9, max_iterations: 40, window_rings: 2, use_window: false,
         selection: least_energy}
output: {every: 5}
)yaml";

TEST_F(SceneYamlTest, CompleteSceneParsesToTheExpectedNumbers) {
  const LoadedScene loaded = LoadFile(kCompleteScene);
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.source, ScenePath());
  EXPECT_EQ(scene.gravity, Eigen::Vector3d(0, 0, -9.81));
  EXPECT_EQ(scene.h, 0.005);
  EXPECT_EQ(scene.duration, 2);

  // obstacles: the ground first, then the list in order
  ASSERT_EQ(scene.obstacles.size(), 3u);
  EXPECT_EQ(scene.obstacles[0].name, "ground");
  EXPECT_EQ(scene.obstacles[0].friction.mu, 0.3);
  EXPECT_EQ(scene.obstacles[0].friction.e_o, 0.8);
  EXPECT_EQ(scene.obstacles[0].friction.e_r, 0.05);
  EXPECT_EQ(scene.obstacles[0].shape->Value(0, Eigen::Vector3d(5, -2, 0.25)), 0.25);
  // the box turned 90° about z spans x ∈ [2, 4], y ∈ [-0.5, 0.5], z ∈ [0, 0.2]
  EXPECT_EQ(scene.obstacles[1].name, "step");
  EXPECT_EQ(scene.obstacles[1].friction.mu, 0.22);  // default friction
  const auto& step = *scene.obstacles[1].shape;
  ASSERT_EQ(step.NumConstraints(), 6);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(4.25, 0, 0.1), Eigen::Vector3d(3, 0.75, 0.1),
                                   Eigen::Vector3d(3, 0, 0.45), Eigen::Vector3d(1.75, 0, 0.1)}) {
    double largest = -1e9;
    for (int i = 0; i < 6; ++i) largest = std::max(largest, step.Value(i, p));
    EXPECT_NEAR(largest, 0.25, kTight) << p.transpose();
  }
  // the plane 3y + 4z = -5 (normal normalized): offset is along the unit normal
  EXPECT_NEAR(scene.obstacles[2].shape->Value(0, Eigen::Vector3d(0, 0, 1)), 0.8 + 1, kTight);

  ASSERT_EQ(scene.bodies.size(), 3u);
  // crate: closed-form box inertia m/12 (b² + c², a² + c², a² + b²)
  const Body& crate = scene.bodies[0];
  EXPECT_EQ(crate.name, "crate");
  EXPECT_EQ(crate.mass, 15);
  EXPECT_NEAR(crate.inertia(0, 0), 15.0 / 12 * (0.16 + 0.01), kTight);
  EXPECT_NEAR(crate.inertia(1, 1), 15.0 / 12 * (0.25 + 0.01), kTight);
  EXPECT_NEAR(crate.inertia(2, 2), 15.0 / 12 * (0.25 + 0.16), kTight);
  EXPECT_EQ(crate.inertia(0, 1), 0);
  EXPECT_EQ(crate.p0, Eigen::Vector3d(0, 0, 0.05));
  EXPECT_EQ(crate.v0, Eigen::Vector3d(0.5, 0, 0));
  EXPECT_EQ(crate.w0, Eigen::Vector3d(0, 0, 1.5));
  EXPECT_TRUE(crate.q0.isApprox(Eigen::Quaterniond::Identity(), 0));
  EXPECT_NEAR(crate.hull->Support(Eigen::Vector3d(1, 1, 1)).x(), 0.25, kTight);

  // cube: 0.5 m edge at 800 kg/m³ = 100 kg, I = m a²/6, CM moved to the body origin
  const Body& cube = scene.bodies[1];
  // kg, kg·m²: the mesh's integrals (~1e-12 relative) times the 100 kg mass
  constexpr double kMeshIntegralRoundOff = 1e-10;
  EXPECT_NEAR(cube.mass, 100, kMeshIntegralRoundOff);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(cube.inertia(k, k), 100 * 0.25 / 6, kMeshIntegralRoundOff);
  EXPECT_NEAR(cube.inertia(0, 1), 0, kMeshIntegralRoundOff);
  ASSERT_EQ(cube.mesh.vertices.size(), 8u);
  for (const Eigen::Vector3d& v : cube.mesh.vertices) {
    EXPECT_NEAR(v.cwiseAbs().maxCoeff(), 0.25, kTight);
    EXPECT_NEAR(v.cwiseAbs().minCoeff(), 0.25, kTight);
  }
  ASSERT_EQ(cube.hull->NumConstraints(), 6);
  EXPECT_NEAR(cube.hull->Support(Eigen::Vector3d(0, 0, -1)).z(), -0.25, kTight);
  EXPECT_EQ(cube.p0, Eigen::Vector3d(1, 2, 3));
  // rpy [90, 0, 0]: R = Rx(90°) turns body y onto world z
  EXPECT_LT((cube.q0 * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), kTight);

  // ball: explicit inertia; the quaternion [0, 0, 0, 2] is normalized to a half turn about z
  const Body& ball = scene.bodies[2];
  EXPECT_EQ(ball.mass, 2);
  EXPECT_EQ(ball.inertia, Eigen::Vector3d(0.1, 0.2, 0.25).asDiagonal().toDenseMatrix());
  EXPECT_EQ(ball.q0.coeffs(), Eigen::Vector4d(0, 0, 1, 0));  // Eigen stores x, y, z, w

  // contacts: every (body, obstacle) pair; the crate's μ override keeps the obstacle's e; then
  // every pair of bodies with the geometric mean of the two bodies' friction (each body's: its
  // overrides over the ground's)
  ASSERT_EQ(scene.contacts.size(), 9u + 3u);
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 3; ++k) {
    const ContactPair& pair = scene.contacts[9 + k];
    EXPECT_EQ(pair.body, pairs[k][0]);
    EXPECT_EQ(pair.other_body, pairs[k][1]);
    EXPECT_EQ(pair.obstacle, -1);
    const Friction expected =
        PairFriction(scene.bodies[pairs[k][0]].friction, scene.bodies[pairs[k][1]].friction);
    EXPECT_EQ(pair.friction.mu, expected.mu);
    EXPECT_EQ(pair.friction.e_r, expected.e_r);
  }
  EXPECT_EQ(scene.bodies[0].friction.mu, 0.1);
  EXPECT_EQ(scene.bodies[1].friction.mu, scene.obstacles[0].friction.mu);
  for (int b = 0; b < 3; ++b) {
    for (int o = 0; o < 3; ++o) {
      const ContactPair& pair = scene.contacts[3 * b + o];
      EXPECT_EQ(pair.body, b);
      EXPECT_EQ(pair.obstacle, o);
      EXPECT_EQ(pair.friction.mu, b == 0 ? 0.1 : scene.obstacles[o].friction.mu);
      EXPECT_EQ(pair.friction.e_o, scene.obstacles[o].friction.e_o);
    }
  }

  ASSERT_EQ(scene.loads.size(), 3u);
  const Load& push = scene.loads[0];
  EXPECT_EQ(push.kind, Load::Kind::kForce);
  EXPECT_EQ(push.body, 0);
  EXPECT_NEAR(push.x(0.25), 45, kTight);
  EXPECT_EQ(push.y(0.25), 0);
  EXPECT_EQ(push.z(0.25), 1);
  EXPECT_EQ(push.start, 0.5);
  EXPECT_EQ(push.end, 1.5);
  // `at` is in the mesh's own frame (after scale): the CM (0.25, 0.25, 0.25) is subtracted
  const Load& lift = scene.loads[1];
  EXPECT_EQ(lift.body, 1);
  EXPECT_TRUE(lift.at_point);
  EXPECT_NEAR((lift.point_B - Eigen::Vector3d(0.25, 0, 0)).norm(), 0, kTight);
  EXPECT_EQ(lift.start, 0);
  EXPECT_GT(lift.end, 1e299);
  EXPECT_EQ(scene.loads[2].kind, Load::Kind::kTorque);
  EXPECT_EQ(scene.loads[2].body, 2);
  EXPECT_NEAR(scene.loads[2].z(0.5), -2.1, kTight);

  ASSERT_EQ(scene.impulses.size(), 1u);
  EXPECT_EQ(scene.impulses[0].body, 1);
  EXPECT_EQ(scene.impulses[0].time, 0.75);
  EXPECT_EQ(scene.impulses[0].linear, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(scene.impulses[0].angular, Eigen::Vector3d(0, 0, 0.5));
  EXPECT_FALSE(scene.impulses[0].at_point);

  EXPECT_EQ(scene.solver.tolerance, 1e-9);
  EXPECT_EQ(scene.solver.max_iterations, 40);
  EXPECT_EQ(scene.solver.window_rings, 2);
  EXPECT_FALSE(scene.solver.use_window);
  EXPECT_EQ(scene.solver.selection, Selection::kLeastEnergy);
  EXPECT_EQ(loaded.output.every, 5);
}

TEST_F(SceneYamlTest, MinimalSceneTakesTheDocumentedDefaults) {
  const LoadedScene loaded = LoadFile(R"yaml(duration: 1
bodies:
  - shape: {box: {size: [1, 1, 1]}}
    density: 10
    position: [0, 0, 0.5]
)yaml");
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.gravity, Eigen::Vector3d(0, 0, -9.8));
  EXPECT_EQ(scene.h, 0.01);
  EXPECT_TRUE(scene.obstacles.empty());
  EXPECT_TRUE(scene.contacts.empty());
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_EQ(scene.bodies[0].name, "body0");
  EXPECT_NEAR(scene.bodies[0].mass, 10, kTight);
  EXPECT_EQ(scene.bodies[0].v0, Eigen::Vector3d::Zero());
  EXPECT_EQ(scene.solver.tolerance, SolverSettings{}.tolerance);
  EXPECT_EQ(scene.solver.max_iterations, SolverSettings{}.max_iterations);
  EXPECT_EQ(scene.solver.selection, Selection::kCreep);
  EXPECT_EQ(loaded.output.every, 1);
  EXPECT_TRUE(loaded.warnings.empty());
}

TEST_F(SceneYamlTest, PrimitivesHaveClosedFormMassAndInertia) {
  const Scene scene = LoadText(R"yaml(duration: 1
bodies:
  - name: can
    shape: {cylinder: {radius: 0.1, length: 0.3, axis: x}}
    density: 1000
    position: [0, 0, 0]
  - name: egg
    shape: {ellipsoid: {radii: [0.1, 0.2, 0.3]}}
    mass: 3
    position: [1, 0, 0]
  - name: ball
    shape: {sphere: {radius: 0.5}}
    mass: 4
    position: [3, 0, 0]
)yaml");
  const Body& can = scene.bodies[0];
  const double m = 1000 * M_PI * 0.01 * 0.3;
  EXPECT_NEAR(can.mass, m, kTight * m);
  EXPECT_NEAR(can.inertia(0, 0), m * 0.01 / 2, kTight);
  EXPECT_NEAR(can.inertia(1, 1), m * (3 * 0.01 + 0.09) / 12, kTight);
  EXPECT_NEAR(can.inertia(2, 2), m * (3 * 0.01 + 0.09) / 12, kTight);
  EXPECT_NEAR(can.hull->Support(Eigen::Vector3d(1, 0, 0)).x(), 0.15, kTight);
  const Body& egg = scene.bodies[1];
  EXPECT_NEAR(egg.inertia(0, 0), 3.0 / 5 * (0.04 + 0.09), kTight);
  EXPECT_NEAR(egg.inertia(2, 2), 3.0 / 5 * (0.01 + 0.04), kTight);
  EXPECT_NEAR(scene.bodies[2].inertia(1, 1), 0.4 * 4 * 0.25, kTight);
}

TEST_F(SceneYamlTest, DeclaredHullPrimitiveReplacesTheMeshHull) {
  // the dumbbell's hull is exactly a cylinder (R = 0.1, L = 0.3) about x
  const Scene scene = LoadText(R"yaml(duration: 1
bodies:
  - mesh: meshes/cube.obj
    scale: 0.1
    hull: {box: {size: [0.2, 0.2, 0.2]}}
    mass: 1
    position: [0, 0, 0]
)yaml");
  EXPECT_NEAR(scene.bodies[0].hull->Support(Eigen::Vector3d(1, 1, 1)).x(), 0.1, kTight);
  EXPECT_THAT(
      [&] {
        LoadText(R"yaml(duration: 1
bodies:
  - mesh: meshes/cube.obj
    hull: {sphere: {radius: 0.6}}
    mass: 1
    position: [0, 0, 0]
)yaml");
      },
      ThrowsMessage<InputError>(AllOf(HasSubstr("scene.yaml:4:11: bodies[0].hull = "),
                                      HasSubstr("contains the mesh"), HasSubstr("outside"))));
}

TEST_F(SceneYamlTest, OnGroundPutsTheLowestHullPointOnZeroAndKeepsXY) {
  // a 0.5 × 0.4 × 0.1 box turned 30° about x: its lowest point is b/2 sin 30° + c/2 cos 30°
  // below the CM
  const Scene scene = LoadText(R"yaml(duration: 1
bodies:
  - shape: {box: {size: [0.5, 0.4, 0.1]}}
    mass: 1
    rpy: [30, 0, 0]
    on_ground: true
    position: [1, 2]
  - shape: {sphere: {radius: 0.2}}
    mass: 1
    lowest_point_height: 0.5
)yaml");
  const double below = 0.2 * 0.5 + 0.05 * std::sqrt(3.0) / 2;
  EXPECT_NEAR(scene.bodies[0].p0.x(), 1, 0);
  EXPECT_NEAR(scene.bodies[0].p0.y(), 2, 0);
  EXPECT_NEAR(scene.bodies[0].p0.z(), below, kTight);
  EXPECT_NEAR(scene.bodies[1].p0.z(), 0.7, kTight);
  EXPECT_THAT(
      [&] {
        LoadText(R"yaml(duration: 1
bodies:
  - shape: {sphere: {radius: 0.2}}
    mass: 1
    on_ground: true
    position: [0, 0, 1]
)yaml");
      },
      ThrowsMessage<InputError>(HasSubstr("scene.yaml:6:15: bodies[0].position = [0, 0, "
                                          "1]: expected [x, y] (m)")));
}

// ---- validation: every message names file:line:col, key, value and expectation --------------

struct BadScene {
  const char* name;
  const char* yaml;
  const char* message;  // expected substring
};

// a valid body that the cases below perturb one key at a time
#define ECPSIM_BODY                       \
  "bodies:\n"                             \
  "  - shape: {box: {size: [1, 1, 1]}}\n" \
  "    position: [0, 0, 0.5]\n"

const BadScene kBadScenes[] = {
    {"UnknownRootKeySuggestsTheClosest", "durration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:1: durration: unknown key (did you mean \"duration\"?); expected one of "
     "gravity, h, duration,"},
    {"UnknownBodyKey", "duration: 1\n" ECPSIM_BODY "    mass: 1\n    colour: red\n",
     "scene.yaml:6:5: bodies[0].colour: unknown key; expected one of name, mesh,"},
    {"UnknownNestedKeySuggestion",
     "duration: 1\nground: {friction: {mu: 0.2, e_x: 1}}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:2:30: ground.friction.e_x: unknown key (did you mean \"e_t\"?)"},
    {"DuplicateKey", "duration: 1\nduration: 2\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:2:1: duration: duplicate key"},
    {"WrongTypeMass", "duration: 1\n" ECPSIM_BODY "    mass: heavy\n",
     "scene.yaml:5:11: bodies[0].mass = heavy: expected a finite mass > 0 kg"},
    {"NegativeMass", "duration: 1\n" ECPSIM_BODY "    mass: -15\n",
     "scene.yaml:5:11: bodies[0].mass = -15: expected a finite mass > 0 kg"},
    {"ZeroDensity", "duration: 1\n" ECPSIM_BODY "    density: 0\n",
     "scene.yaml:5:14: bodies[0].density = 0: expected a finite density > 0 kg/m³"},
    {"MassAndDensity", "duration: 1\n" ECPSIM_BODY "    mass: 1\n    density: 2\n",
     "scene.yaml:6:14: bodies[0].density = 2: expected either `mass` or `density`, not both"},
    {"MissingMass", "duration: 1\n" ECPSIM_BODY,
     "scene.yaml:3:5: bodies[0].mass = (missing): expected a mass > 0 kg (or a `density`"},
    {"MissingDuration", ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:1: duration = (missing): expected a duration > 0 s"},
    {"MissingBodies", "duration: 1\n",
     "scene.yaml:1:1: bodies = (missing): expected a list of at least one body"},
    {"MissingShape", "duration: 1\nbodies:\n  - mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:5: bodies[0].mesh = (missing): expected exactly one of `mesh: FILE` or "
     "`shape:"},
    {"MissingPosition", "duration: 1\nbodies:\n  - shape: {sphere: {radius: 1}}\n    mass: 1\n",
     "scene.yaml:3:5: bodies[0].position = (missing): expected [x, y, z] (m)"},
    {"NonFiniteStep", "h: .inf\nduration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:4: h = .inf: expected a finite time step > 0 s"},
    {"NaNGravity", "gravity: [0, 0, .nan]\nduration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:17: gravity[2] = .nan: expected a list of 3 finite numbers"},
    {"ZeroStep", "h: 0\nduration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:4: h = 0: expected a finite time step > 0 s"},
    {"StepLongerThanDuration", "h: 2\nduration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:4: h = 2: expected a time step <= duration = 1 s"},
    {"DurationShorterThanDefaultStep", "duration: 0.005\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:11: duration = 0.005: expected a duration >= the default time step h = 0.01 s"},
    {"NegativeDuration", "duration: -1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:11: duration = -1: expected a finite duration > 0 s"},
    {"NegativeMu", "duration: 1\nground: {friction: {mu: -0.1}}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:2:25: ground.friction.mu = -0.1: expected a friction coefficient >= 0"},
    {"ZeroEllipsoidAxis", "duration: 1\nground: {friction: {e_r: 0}}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:2:26: ground.friction.e_r = 0: expected a torsional ellipsoid semi-axis > 0 m"},
    {"MisspelledPatch",
     "duration: 1\nground: {friction: {e_r: pach}}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:2:26: ground.friction.e_r = pach: expected a torsional ellipsoid semi-axis > 0 m, "
     "or `patch`"},
    {"NegativeBodyFrictionE", "duration: 1\n" ECPSIM_BODY "    mass: 1\n    friction: {e_t: -1}\n",
     "scene.yaml:6:21: bodies[0].friction.e_t = -1: expected an ellipsoid semi-axis > 0"},
    {"ZeroNormal",
     "duration: 1\nobstacles:\n  - plane: {normal: [0, 0, 0]}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:3:21: obstacles[0].plane.normal = [0, 0, 0]: expected a non-zero normal"},
    {"PlaneAndBox",
     "duration: 1\nobstacles:\n  - plane: {}\n    box: {size: [1, 1, 1]}\n" ECPSIM_BODY
     "    mass: 1\n",
     "scene.yaml:3:5: obstacles[0] = {plane: {}, box: {size: [1, 1, 1]}}: expected exactly one of"},
    {"FlatBoxObstacle",
     "duration: 1\nobstacles:\n  - box: {size: [1, 0, 1]}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:3:17: obstacles[0].box.size = [1, 0, 1]: expected a list of 3 edge lengths > 0 m"},
    {"MissingMeshFile",
     "duration: 1\nbodies:\n  - mesh: meshes/nope.obj\n    mass: 1\n"
     "    position: [0, 0, 0]\n",
     "scene.yaml:3:11: bodies[0].mesh = meshes/nope.obj: expected an existing mesh file (looked "
     "for "},
    {"ZeroQuaternion", "duration: 1\n" ECPSIM_BODY "    mass: 1\n    quaternion: [0, 0, 0, 0]\n",
     "scene.yaml:6:17: bodies[0].quaternion = [0, 0, 0, 0]: expected a non-zero quaternion"},
    {"ShortQuaternion", "duration: 1\n" ECPSIM_BODY "    mass: 1\n    quaternion: [1, 0, 0]\n",
     "scene.yaml:6:17: bodies[0].quaternion = [1, 0, 0]: expected a list of 4 finite numbers"},
    {"QuaternionAndRpy",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n    rpy: [0, 0, 0]\n"
     "    quaternion: [1, 0, 0, 0]\n",
     "scene.yaml:6:10: bodies[0].rpy = [0, 0, 0]: expected either `quaternion` or `rpy`"},
    {"InertiaNotPositiveDefinite",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n    inertia: [1, 1, -1]\n",
     "scene.yaml:6:14: bodies[0].inertia = [1, 1, -1]: expected an inertia of body \"body0\" "
     "(kg·m², about the CM in body axes) that is symmetric, positive definite"},
    {"InertiaViolatesTriangleInequality",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n    inertia: [1, 1, 3]\n",
     "scene.yaml:6:14: bodies[0].inertia = [1, 1, 3]: expected an inertia of body \"body0\" "
     "(kg·m², about the CM in body axes) that is symmetric, positive definite, each principal "
     "moment <= the sum of the other two"},
    {"InertiaWithoutMass", "duration: 1\n" ECPSIM_BODY "    density: 1\n    inertia: [1, 1, 1]\n",
     "scene.yaml:6:14: bodies[0].inertia = [1, 1, 1]: expected `inertia` together with `mass`"},
    {"BadName",
     "duration: 1\nbodies:\n  - name: my box\n    shape: {sphere: {radius: 1}}\n"
     "    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:11: bodies[0].name = my box: expected a name of letters, digits"},
    {"DuplicateBodyName",
     "duration: 1\nbodies:\n  - name: a\n    shape: {sphere: {radius: 1}}\n"
     "    mass: 1\n    position: [0, 0, 0]\n  - name: a\n    shape: {sphere: {radius: 1}}\n"
     "    mass: 1\n    position: [0, 0, 3]\n",
     "scene.yaml:7:11: bodies[1].name = a: expected a name no other body has"},
    {"BadCylinderAxis",
     "duration: 1\nbodies:\n  - shape: {cylinder: {radius: 1, length: 1, "
     "axis: w}}\n    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:52: bodies[0].shape.cylinder.axis = w: expected an axis x, y or z"},
    {"TwoPrimitives",
     "duration: 1\nbodies:\n  - shape: {sphere: {radius: 1}, box: {size: [1, 1, "
     "1]}}\n    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:12: bodies[0].shape = {sphere: {radius: 1}, box: {size: [1, 1, 1]}}: expected "
     "exactly one of box, sphere, cylinder, ellipsoid"},
    {"BadExpression",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nloads:\n  - force: [\"sin(2*t\", 0, 0]\n",
     "scene.yaml:7:13: loads[0].force[0] = \"sin(2*t\": Missing parenthesis"},
    {"UnknownVariableInExpression",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nloads:\n  - torque: [0, 0, \"2*omega\"]\n",
     "scene.yaml:7:20: loads[0].torque[2] = \"2*omega\": Unexpected token \"omega\""},
    {"ForceAndTorque",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nloads:\n  - {force: [0, 0, 1], torque: [0, 0, 1]}\n",
     "scene.yaml:7:5: loads[0] = {force: [0, 0, 1], torque: [0, 0, 1]}: expected exactly one of"},
    {"LoadEndBeforeStart",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nloads:\n  - {force: [0, 0, 1], start: 2, end: 1}\n",
     "scene.yaml:7:39: loads[0].end = 1: expected an end time (s) > start = 2"},
    {"TorqueAtPoint",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nloads:\n  - {torque: [0, 0, 1], at: [1, 0, 0]}\n",
     "scene.yaml:7:29: loads[0].at = [1, 0, 0]: expected `at` only with a force"},
    {"UnknownBody",
     "duration: 1\n" ECPSIM_BODY
     "    mass: 1\nimpulses:\n  - {body: crate, time: 0, linear: [1, 0, 0]}\n",
     "scene.yaml:7:12: impulses[0].body = crate: expected a body name (body0) or index 0..0"},
    {"NegativeImpulseTime",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nimpulses:\n  - {time: -1, linear: [1, 0, 0]}\n",
     "scene.yaml:7:12: impulses[0].time = -1: expected a finite time >= 0 s"},
    {"SolverIterationsNotInteger",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nsolver: {max_iterations: 2.5}\n",
     "scene.yaml:6:26: solver.max_iterations = 2.5: expected an integer >= 1"},
    {"SolverZeroTolerance", "duration: 1\n" ECPSIM_BODY "    mass: 1\nsolver: {tolerance: 0}\n",
     "scene.yaml:6:21: solver.tolerance = 0: expected a residual tolerance > 0"},
    {"OutputEveryZero", "duration: 1\n" ECPSIM_BODY "    mass: 1\noutput: {every: 0}\n",
     "scene.yaml:6:17: output.every = 0: expected an integer >= 1"},
    {"BodiesNotAList", "duration: 1\nbodies: {mass: 1}\n",
     "scene.yaml:2:9: bodies = {mass: 1}: expected a list of at least one body"},
    {"SyntaxError", "duration: [1, 2\nbodies: []\n", "scene.yaml:2:"},
    // ---- values whose derived quantities would overflow, underflow or lose the run's steps
    {"TooManySteps", "h: 1e-16\nduration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:4: h = 1e-16: expected at most 4503599627370496 steps per run, here duration / "
     "h = 1 / 1e-16 = 1e+16 steps"},
    {"DurationBeyondTheStepLimit", "duration: 1e20\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:11: duration = 1e20: expected at most 4503599627370496 steps per run"},
    {"StepUnderflows", "h: 1e-300\nduration: 1\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:1:4: h = 1e-300: expected a time in [1e-150, 1e+150] s"},
    {"QuaternionOverflows",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n    quaternion: [1e200, 1e200, 1e200, 1e200]\n",
     "scene.yaml:6:18: bodies[0].quaternion[0] = 1e200: expected a list of 4 finite numbers [w, x, "
     "y, z], not all zero; each a finite number within ±1e+150"},
    {"HugeBox",
     "duration: 1\nbodies:\n  - shape: {box: {size: [1e200, 1e200, 1e200]}}\n"
     "    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:25: bodies[0].shape.box.size = [1e200, 1e200, 1e200]: expected a list of 3 "
     "edge lengths > 0 m [x, y, z], each a length in [1e-20, 1e+20] m"},
    {"TinyBox",
     "duration: 1\nbodies:\n  - shape: {box: {size: [1e-200, 1, 1]}}\n"
     "    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:25: bodies[0].shape.box.size = [1e-200, 1, 1]: expected a list of 3 edge "
     "lengths > 0 m [x, y, z], each a length in [1e-20, 1e+20] m"},
    {"HugeSphere",
     "duration: 1\nbodies:\n  - shape: {sphere: {radius: 1e31}}\n"
     "    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:3:30: bodies[0].shape.sphere.radius = 1e31: expected a length in [1e-20, "
     "1e+20] m"},
    {"MassTooLarge", "duration: 1\n" ECPSIM_BODY "    mass: 1e151\n",
     "scene.yaml:5:11: bodies[0].mass = 1e151: expected a mass in [1e-150, 1e+150] kg"},
    {"DensityOverflowsTheMass",
     "duration: 1\nbodies:\n  - shape: {box: {size: [1e19, 1e19, "
     "1e19]}}\n    density: 1e100\n    position: [0, 0, 0]\n",
     "scene.yaml:4:14: bodies[0].density = 1e100: expected a mass of body \"body0\" that is a mass "
     "in [1e-150, 1e+150] kg; it is 1e+157 kg"},
    {"InertiaUnderflows", "duration: 1\n" ECPSIM_BODY "    mass: 2e-150\n",
     "scene.yaml:5:11: bodies[0].mass = 2e-150: expected principal moments of body \"body0\" that "
     "are each a principal moment of inertia in [1e-150, 1e+150] kg·m²; it is 3.33e-151"},
    {"VelocityOverflowsWhenSquared",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n    velocity: [1e151, 0, 0]\n",
     "scene.yaml:6:16: bodies[0].velocity[0] = 1e151: expected a list of 3 finite numbers"},
    {"FarFromTheOrigin",
     "duration: 1\nbodies:\n  - shape: {box: {size: [1, 1, 1]}}\n"
     "    position: [1e8, 0, 0.5]\n    mass: 1\n",
     "scene.yaml:4:15: bodies[0].position = [1e8, 0, 0.5]: expected body \"body0\" within 1e+06 × "
     "its size 1.73 m of the origin"},
    {"NulInExpression",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nloads:\n  - force: [\"t\\0*1000\", 0, 0]\n",
     "scene.yaml:7:13: loads[0].force[0] = t\\x00*1000: expected a number or an expression of t in "
     "quotes, without NUL characters"},
    {"NulInMeshPath",
     "duration: 1\nbodies:\n  - mesh: \"meshes/cube.obj\\0.stl\"\n    mass: 1\n"
     "    position: [0, 0, 0]\n",
     "scene.yaml:3:11: bodies[0].mesh = meshes/cube.obj\\x00.stl: expected a mesh file path "
     "(relative to the scene file), without NUL characters"},
    {"StepLimitOfTheSolver",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\nsolver: {max_iterations: 100000}\n",
     "scene.yaml:6:26: solver.max_iterations = 100000: expected an integer in [1, 10000]"},
    {"FrameTooWide", "duration: 1\n" ECPSIM_BODY "    mass: 1\noutput: {width: 100000}\n",
     "scene.yaml:6:17: output.width = 100000: expected an integer in [16, 8192]"},
    // ---- an initial overlap with an obstacle
    {"InitialPenetration",
     "duration: 1\nground: {}\n" ECPSIM_BODY "    mass: 1\n"
     "    rpy: [45, 0, 0]\n",
     "scene.yaml:5:15: bodies[0].position = [0, 0, 0.5]: expected an initial pose of body "
     "\"body0\" whose mesh stays out of obstacle \"ground\""},
    {"InitialPenetrationOfABoxFixture",
     "duration: 1\nground: {}\nobstacles:\n  - name: step\n"
     "    box: {size: [1, 1, 1], position: [0, 0, 0.5]}\nbodies:\n  - shape: {sphere: {radius: "
     "0.25}}\n    mass: 1\n    on_ground: true\n",
     "scene.yaml:9:16: bodies[0].on_ground = true: expected an initial pose of body \"body0\" "
     "whose mesh stays out of obstacle \"step\": a vertex is 0.5 m inside"},
    {"BoxFixtureFarFromTheOrigin",
     "duration: 1\nobstacles:\n  - box: {size: [1e-3, 1e-3, 1e-3], "
     "position: [1e150, 0, 0]}\n" ECPSIM_BODY "    mass: 1\n",
     "scene.yaml:3:47: obstacles[0].box.position = [1e150, 0, 0]: expected obstacle \"obstacle0\" "
     "within 1e+06 × its size"},
    {"DuplicateObstacleNameAfterTheGround",
     "duration: 1\nground: {}\nobstacles:\n"
     "  - {name: a, plane: {offset: -5}}\n  - {name: a, plane: {offset: -6}}\n" ECPSIM_BODY
     "    mass: 1\n",
     "scene.yaml:5:12: obstacles[1].name = a: expected a name no other obstacle has"},
    // ---- mesh units
    {"UnknownUnit",
     "duration: 1\nbodies:\n  - mesh: meshes/cube.obj\n    units: ft\n"
     "    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:4:12: bodies[0].units = ft: expected one of mm, cm, m, in"},
    {"UnitsDisagreeWithScale",
     "duration: 1\nbodies:\n  - mesh: meshes/cube.obj\n    units: mm\n"
     "    scale: 0.01\n    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:4:12: bodies[0].units = mm: expected a unit agreeing with bodies[0].scale = 0.01 "
     "(mm is 0.001 m)"},
    {"UnitsWithoutMesh", "duration: 1\n" ECPSIM_BODY "    mass: 1\n    units: mm\n",
     "scene.yaml:6:12: bodies[0].units = mm: expected `units` only together with `mesh`"},
    {"ScaleOutOfRange",
     "duration: 1\nbodies:\n  - mesh: meshes/cube.obj\n    scale: 1e200\n"
     "    mass: 1\n    position: [0, 0, 0]\n",
     "scene.yaml:4:12: bodies[0].scale = 1e200: expected a scale in [1e-06, 1e+06]"},
    // ---- kinematic bodies and pairs
    {"KinematicWithMass",
     "duration: 1\nbodies:\n  - kinematic: true\n    mass: 1\n"
     "    shape: {box: {size: [1, 1, 1]}}\n    motion: {velocity: {position: [0, 0, 1]}}\n",
     "scene.yaml:4:11: bodies[0].mass = 1: expected no `mass` on a kinematic body"},
    {"KinematicWithoutMotion",
     "duration: 1\nbodies:\n  - kinematic: true\n"
     "    shape: {box: {size: [1, 1, 1]}}\n",
     "bodies[0].motion"},
    {"MotionWithoutKinematic",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n"
     "    motion: {velocity: {position: [0, 0, 1]}}\n",
     "expected `motion` only on a body with `kinematic: true`"},
    {"LoadOnAKinematicBody",
     "duration: 1\nbodies:\n  - name: finger\n    kinematic: true\n"
     "    shape: {box: {size: [1, 1, 1]}}\n    motion: {velocity: {position: [0, 0, 1]}}\n"
     "loads:\n  - {body: finger, force: [1, 0, 0]}\n",
     "expected a dynamic body (a kinematic body's motion is prescribed"},
    {"PairOfAnUnknownBody",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n"
     "pairs:\n  - {bodies: [body0, ghost]}\n",
     "scene.yaml:7:22: pairs[0].bodies[1] = ghost: expected the name of a body of the scene "
     "(body0)"},
    {"PairOfOneBody",
     "duration: 1\n" ECPSIM_BODY "    mass: 1\n"
     "pairs:\n  - {bodies: [body0, body0]}\n",
     "pairs[0].bodies = [body0, body0]: expected two different bodies"},
// ---- grippers
#define ECPSIM_JAWS(A_EXTRA)                                                                  \
  "duration: 1\nbodies:\n"                                                                    \
  "  - {name: a, shape: {box: {size: [0.01, 0.04, 0.03]}}, mass: 0.05, position: [-0.05, 0, " \
  "0.5]" A_EXTRA                                                                              \
  "}\n"                                                                                       \
  "  - {name: b, shape: {box: {size: [0.01, 0.04, 0.03]}}, mass: 0.05, position: [0.05, 0, "  \
  "0.5]}\n"
#define ECPSIM_FRAME "motion: {velocity: {position: [0, 0, 0.5]}}"
    {"GripperOfAnUnknownJaw",
     ECPSIM_JAWS("") "grippers:\n  - {jaws: [a, ghost], axis: [1, 0, 0], force: 1, " ECPSIM_FRAME
                     "}\n",
     "grippers[0].jaws[1] = ghost: expected the name of a body of the scene (a, b)"},
    {"GripperWithOneJawTwice",
     ECPSIM_JAWS("") "grippers:\n  - {jaws: [a, a], axis: [1, 0, 0], force: 1, " ECPSIM_FRAME "}\n",
     "grippers[0].jaws[1] = a: expected a body that is no other jaw (it is one of this "
     "gripper's already)"},
    {"UnknownSelection", "duration: 1\n" ECPSIM_BODY "    mass: 1\nsolver: {selection: least}\n",
     "solver.selection = least: expected one of creep, least_energy"},
    {"GripperWithAZeroAxis",
     ECPSIM_JAWS("") "grippers:\n  - {jaws: [a, b], axis: [0, 0, 0], force: 1, " ECPSIM_FRAME "}\n",
     "grippers[0].axis = [0, 0, 0]: expected a non-zero axis"},
    {"GripperWhoseAxisPointsFromTheSecondJaw",
     ECPSIM_JAWS("") "grippers:\n  - {jaws: [a, b], axis: [-1, 0, 0], force: 1, " ECPSIM_FRAME
                     "}\n",
     "expected an axis from jaw \"a\" towards jaw \"b\" (their centres are -0.1 m apart along it "
     "at t = 0; swap the jaws or flip the axis)"},
    {"GripperPullingItsJawsOpen",
     ECPSIM_JAWS("") "grippers:\n  - {jaws: [a, b], axis: [1, 0, 0], force: -1, " ECPSIM_FRAME
                     "}\n",
     "grippers[0].force = -1: expected a closing force ≥ 0 N at t = 0"},
    {"GripperWithoutForce",
     ECPSIM_JAWS("") "grippers:\n  - {jaws: [a, b], axis: [1, 0, 0], " ECPSIM_FRAME "}\n",
     "grippers[0].force"},
    {"JawWithAnInitialVelocity",
     ECPSIM_JAWS(", velocity: [0, 1, 0]") "grippers:\n  - {jaws: [a, b], axis: [1, 0, 0], force: "
                                          "1, " ECPSIM_FRAME "}\n",
     "expected no initial velocity for jaw \"a\" of gripper \"gripper0\" (the gripper moves it)"},
#undef ECPSIM_FRAME
#undef ECPSIM_JAWS
};
#undef ECPSIM_BODY

class BadSceneTest : public SceneYamlTest, public ::testing::WithParamInterface<BadScene> {};

TEST_P(BadSceneTest, IsRejectedWithItsLocationAndExpectation) {
  const BadScene& bad = GetParam();
  EXPECT_THAT([&] { LoadText(bad.yaml); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(ScenePath()), HasSubstr(bad.message))));
}

INSTANTIATE_TEST_SUITE_P(Validation, BadSceneTest, ::testing::ValuesIn(kBadScenes),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST_F(SceneYamlTest, KinematicBodiesAndPairSettingsMakeTheDocumentedContacts) {
  const Scene scene = LoadText(
      "duration: 1\nground: {friction: {mu: 0.4}}\nbodies:\n"
      "  - {name: a, shape: {box: {size: [0.2, 0.2, 0.2]}}, mass: 1, position: [0, 0, 0.1]}\n"
      "  - {name: b, shape: {box: {size: [0.2, 0.2, 0.2]}}, mass: 1, position: [1, 0, 0.1],\n"
      "     friction: {mu: 0.1}}\n"
      "  - name: finger\n    kinematic: true\n    shape: {sphere: {radius: 0.01}}\n"
      "    motion: {velocity: {position: [-0.5, 0, 0.1], linear: [0.1, 0, 0]}}\n"
      "pairs:\n  - {bodies: [b, a], friction: {mu: 0.3}}\n  - {bodies: [finger, b], exclude: "
      "true}\n");
  // obstacle contacts for the two dynamic bodies only; then a–b (overridden) and a–finger (F a,
  // G the kinematic finger), b–finger excluded
  ASSERT_EQ(scene.contacts.size(), 4u);
  EXPECT_TRUE(scene.bodies[2].IsKinematic());
  EXPECT_EQ(scene.bodies[2].p0, Eigen::Vector3d(-0.5, 0, 0.1));
  EXPECT_EQ(scene.contacts[2].body, 0);
  EXPECT_EQ(scene.contacts[2].other_body, 1);
  EXPECT_EQ(scene.contacts[2].friction.mu, 0.3);
  EXPECT_EQ(scene.contacts[3].body, 0);
  EXPECT_EQ(scene.contacts[3].other_body, 2);
  EXPECT_EQ(scene.contacts[3].friction.mu, 0.4);  // sqrt(0.4 · 0.4): a and the finger
}

TEST_F(SceneYamlTest, TheShippedGripperCarriesItsJawsAtTheirPlacesInItsFrame) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/gripper.yaml").scene;
  ASSERT_EQ(scene.grippers.size(), 1u);
  const Gripper& hand = scene.grippers[0];
  EXPECT_EQ(hand.name, "hand");
  EXPECT_EQ(scene.bodies[hand.jaws[0]].name, "left_jaw");
  EXPECT_EQ(scene.bodies[hand.jaws[1]].name, "right_jaw");
  EXPECT_EQ(scene.bodies[hand.jaws[0]].gripper, 0);
  EXPECT_FALSE(scene.bodies[0].IsJaw());
  EXPECT_EQ(hand.axis, Eigen::Vector3d::UnitX());
  // the frame starts at (0, 0, 0.04), the jaws 5 cm to either side of it
  EXPECT_EQ(hand.jaw_in_frame[0].p, Eigen::Vector3d(-0.05, 0, 0));
  EXPECT_EQ(hand.jaw_in_frame[1].p, Eigen::Vector3d(0.05, 0, 0));
  EXPECT_EQ(hand.force(0.1), 0.2);
  EXPECT_EQ(hand.force(1), 5);
  EXPECT_EQ(hand.force(2.7), 0);
}

TEST_F(SceneYamlTest, SyntaxErrorIsReportedAsYamlError) {
  EXPECT_THAT([&] { LoadText("duration: [1, 2\nbodies: []\n"); },
              ThrowsMessage<InputError>(HasSubstr("YAML syntax error")));
}

TEST_F(SceneYamlTest, MissingSceneFileIsAnInputError) {
  EXPECT_THAT([&] { LoadScene((dir_ / "absent.yaml").string()); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("absent.yaml"), HasSubstr("cannot open"))));
}

// ---- overrides -------------------------------------------------------------------------------

constexpr const char* kOneBox = R"yaml(duration: 1
bodies:
  - name: box
    shape: {box: {size: [1, 1, 1]}}
    mass: 2
    position: [0, 0, 0.5]
)yaml";

TEST_F(SceneYamlTest, OverridesReplaceAndAddValuesBeforeValidation) {
  const Scene scene = LoadText(kOneBox, {"h=0.005", "bodies.0.mass=3", "solver.tolerance=1e-9",
                                         "gravity=[0, 0, -1]", "bodies.0.velocity=[1, 2, 3]"});
  EXPECT_EQ(scene.h, 0.005);
  EXPECT_EQ(scene.bodies[0].mass, 3);
  EXPECT_NEAR(scene.bodies[0].inertia(0, 0), 3.0 / 6, kTight);
  EXPECT_EQ(scene.solver.tolerance, 1e-9);
  EXPECT_EQ(scene.gravity, Eigen::Vector3d(0, 0, -1));
  EXPECT_EQ(scene.bodies[0].v0, Eigen::Vector3d(1, 2, 3));
}

TEST_F(SceneYamlTest, BadOverrideKeysAndValuesAreNamed) {
  EXPECT_THAT([&] { LoadText(kOneBox, {"bodies.0.mas=3"}); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("--set bodies.0.mas=3"),
                                              HasSubstr("bodies[0].mas: unknown key (did you mean "
                                                        "\"mass\"?)"))));
  EXPECT_THAT([&] { LoadText(kOneBox, {"bodies.3.mass=1"}); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("--set bodies.3.mass=1"),
                                              HasSubstr("bodies is a list of 1 entries"))));
  EXPECT_THAT([&] { LoadText(kOneBox, {"duration.x=1"}); },
              ThrowsMessage<InputError>(HasSubstr("--set duration.x=1: duration = 1 is a value")));
  EXPECT_THAT([&] { LoadText(kOneBox, {"h"}); },
              ThrowsMessage<InputError>(HasSubstr("--set h: expected key=value")));
  EXPECT_THAT([&] { LoadText(kOneBox, {"h=-1"}); },
              ThrowsMessage<InputError>(
                  HasSubstr("--set h=-1: h = -1: expected a finite time step > 0 s")));
  EXPECT_THAT([&] { LoadText(kOneBox, {"h=[1, 2"}); },
              ThrowsMessage<InputError>(HasSubstr("--set h=[1, 2: the value is not valid YAML")));
}

// ---- files and paths -------------------------------------------------------------------------

TEST_F(SceneYamlTest, MeshPathsAreRelativeToTheSceneFile) {
  const std::string path = Write("scenes/deep/cube_scene.yaml", R"yaml(duration: 1
bodies:
  - mesh: ../../meshes/cube.obj
    mass: 6
    position: [0, 0, 0]
)yaml");
  // loading from another working directory must not matter
  const fs::path cwd = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  const Scene scene = LoadScene(path).scene;
  fs::current_path(cwd);
  EXPECT_NEAR(scene.bodies[0].mass, 6, kTight);
  EXPECT_NEAR(scene.bodies[0].inertia(2, 2), 6.0 / 6, kTight);
}

TEST_F(SceneYamlTest, UnitsScaleTheMeshLikeScale) {
  const Scene scene = LoadText(R"yaml(duration: 1
bodies:
  - mesh: meshes/cube.obj
    units: cm
    density: 1000
    position: [0, 0, 0]
  - mesh: meshes/cube.obj
    units: in
    scale: 0.0254
    mass: 1
    position: [1, 0, 0]
)yaml");
  // a 1 cm cube of water: 1 g, I = m a² / 6
  EXPECT_NEAR(scene.bodies[0].mass, 1e-3, 1e-3 * kTight);
  EXPECT_NEAR(scene.bodies[0].inertia(0, 0), 1e-3 * 1e-4 / 6, 1e-7 * kTight);
  EXPECT_NEAR(scene.bodies[1].hull->Support(Eigen::Vector3d(1, 1, 1)).x(), 0.0127, kTight);
}

TEST_F(SceneYamlTest, MeshOfImplausibleSizeGivesAWarningNamingTheSceneKeys) {
  // a 1 m cube scaled to 100 m edges (173 m across)
  const LoadedScene large = LoadFile(R"yaml(duration: 1
bodies:
  - mesh: meshes/cube.obj
    scale: 100
    mass: 1
    position: [0, 0, 0]
)yaml");
  ASSERT_EQ(large.warnings.size(), 1u);
  EXPECT_EQ(large.warnings[0],
            fmt::format("{}:3:11: bodies[0].mesh: {} is 173 m across; if it is in metres use "
                        "bodies[0].units: m (or bodies[0].scale: 1)",
                        ScenePath(), (dir_ / "meshes/cube.obj").string()));
  // a 0.5 m cube: no warning
  const LoadedScene plausible = LoadFile(R"yaml(duration: 1
bodies:
  - mesh: meshes/cube.obj
    scale: 0.5
    mass: 1
    position: [0, 0, 0]
)yaml");
  EXPECT_TRUE(plausible.warnings.empty());
}

TEST_F(SceneYamlTest, MeshWhoseSizeOverflowsItsInertiaIsLocated) {
  // the unit cube's OBJ with every coordinate 1 written as 1e30
  const std::string cube = kCubeObj;
  std::string huge;
  for (const char c : cube.substr(0, cube.find("f "))) {
    huge += c == '1' ? std::string("1e30") : std::string(1, c);
  }
  Write("meshes/huge.obj", huge + cube.substr(cube.find("f ")));
  EXPECT_THAT(
      [&] {
        LoadText(
            "duration: 1\nbodies:\n  - mesh: meshes/huge.obj\n    mass: 1\n"
            "    position: [0, 0, 0]\n");
      },
      ThrowsMessage<InputError>(
          AllOf(HasSubstr("scene.yaml:3:11: bodies[0].mesh: "),
                HasSubstr("huge.obj: scale = 1 makes the mesh 1.73e+30 m across"),
                HasSubstr("expected a bounding-box diagonal between 1e-20 m and 1e+20 m"))));
}

TEST_F(SceneYamlTest, InitialPenetrationIsAllowedPerBody) {
  const Scene scene = LoadText(R"yaml(duration: 1
ground: {}
bodies:
  - shape: {box: {size: [1, 1, 1]}}
    mass: 1
    position: [0, 0, 0.1]
    allow_initial_penetration: true
)yaml");
  EXPECT_TRUE(scene.bodies[0].allow_initial_penetration);
  EXPECT_THAT(
      [&] {
        LoadText(
            "duration: 1\nground: {}\nbodies:\n  - shape: {box: {size: [1, 1, 1]}}\n"
            "    mass: 1\n    position: [0, 0, 0.1]\n");
      },
      ThrowsMessage<InputError>(HasSubstr(
          "scene.yaml:6:15: bodies[0].position = [0, 0, 0.1]: expected an initial pose of "
          "body \"body0\" whose mesh stays out of obstacle \"ground\": a vertex is 0.4 m "
          "inside, more than 1.73e-06 m (1e-06 × the body's size 1.73 m); move the body, "
          "or allow it with bodies[0].allow_initial_penetration: true")));
}

TEST_F(SceneYamlTest, ValidationErrorsOfOverriddenValuesNameTheSet) {
  EXPECT_THAT(
      [&] {
        LoadText(
            "duration: 1\nground: {}\n"
            "bodies:\n  - shape: {box: {size: [1, 1, 1]}}\n"
            "    mass: 1\n    position: [0, 0, 0.5]\n",
            {"bodies.0.position=[0, 0, 0.1]"});
      },
      ThrowsMessage<InputError>(
          HasSubstr("scene.yaml: --set bodies.0.position=[0, 0, 0.1]: bodies[0].position = "
                    "[0, 0, 0.1]: expected an initial pose")));
}

TEST_F(SceneYamlTest, ShippedSlideSceneLoadsWithThePaperNumbers) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/slide.yaml").scene;
  EXPECT_EQ(scene.h, 0.01);
  EXPECT_EQ(scene.duration, 0.5);
  EXPECT_EQ(scene.gravity, Eigen::Vector3d(0, 0, -9.8));
  ASSERT_EQ(scene.bodies.size(), 1u);
  ASSERT_EQ(scene.obstacles.size(), 1u);
  ASSERT_EQ(scene.contacts.size(), 1u);
  const Body& box = scene.bodies[0];
  EXPECT_EQ(box.mass, 15);
  EXPECT_NEAR(box.p0.z(), 0.05, kTight);
  EXPECT_EQ(box.v0, Eigen::Vector3d(0.5, 0, 0));
  EXPECT_NEAR(box.inertia(2, 2), 15.0 / 12 * 0.5, kTight);
  EXPECT_NEAR(box.hull->Support(-Eigen::Vector3d::UnitZ()).z(), -0.05, kTight);
  const Friction& f = scene.contacts[0].friction;
  EXPECT_EQ(f.mu, 0.22);
  EXPECT_EQ(f.e_t, 1);
  EXPECT_EQ(f.e_o, 1);
  EXPECT_EQ(f.e_r, 0.1);
}

// `e_r: patch` wherever a friction mapping is: a body's keys override the obstacle's (a number
// over `patch` and `patch` over a number); two bodies' pair is patch if either asks for it; a
// `pairs:` entry's own friction decides
TEST_F(SceneYamlTest, ErPatchIsReadPerObstacleBodyAndPair) {
  const Scene scene = LoadText(R"(duration: 1
ground: {friction: {mu: 0.3, e_r: patch}}
obstacles:
  - plane: {normal: [-1, 0, 0], offset: -5}
    friction: {e_r: 0.02}
bodies:
  - name: a
    shape: {box: {size: [0.2, 0.2, 0.2]}}
    position: [0, 0, 0.1]
    mass: 1
  - name: b
    shape: {box: {size: [0.2, 0.2, 0.2]}}
    position: [1, 0, 0.1]
    mass: 1
    friction: {e_r: 0.05}
  - name: c
    shape: {box: {size: [0.2, 0.2, 0.2]}}
    position: [2, 0, 0.1]
    mass: 1
    friction: {e_r: 0.05}
pairs:
  - bodies: [b, c]
    friction: {e_r: patch}
)");
  ASSERT_EQ(scene.contacts.size(), 3u * 2u + 3u);
  // a with the ground: the ground's patch; a with the wall: the wall's number
  EXPECT_TRUE(scene.contacts[0].friction.e_r_patch);
  EXPECT_FALSE(scene.contacts[1].friction.e_r_patch);
  EXPECT_EQ(scene.contacts[1].friction.e_r, 0.02);
  // b's number over the ground's patch, and over the wall's number
  EXPECT_FALSE(scene.contacts[2].friction.e_r_patch);
  EXPECT_EQ(scene.contacts[2].friction.e_r, 0.05);
  EXPECT_EQ(scene.contacts[3].friction.e_r, 0.05);
  // body pairs: a (patch, from the ground) with b (0.05): patch; a with c: patch; b with c: their
  // numbers' mean, but the pair's own `e_r: patch` decides
  EXPECT_TRUE(scene.contacts[6].friction.e_r_patch);
  EXPECT_TRUE(scene.contacts[7].friction.e_r_patch);
  EXPECT_TRUE(scene.contacts[8].friction.e_r_patch);
  // and --set reaches it as any key
  const Scene set = LoadText(
      "duration: 1\nground: {friction: {e_r: 0.1}}\nbodies:\n  - shape: {box: {size: [1, 1, 1]}}\n"
      "    position: [0, 0, 0.5]\n    mass: 1\n",
      {"ground.friction.e_r=patch"});
  ASSERT_EQ(set.contacts.size(), 1u);
  EXPECT_TRUE(set.contacts[0].friction.e_r_patch);
}

TEST_F(SceneYamlTest, ShippedTiltedBoxStandsOnOneEdge) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/tilted_box.yaml").scene;
  ASSERT_EQ(scene.bodies.size(), 1u);
  const Body& box = scene.bodies[0];
  // released at rest, tilted about x, the lowest hull point exactly on the ground z = 0
  const Eigen::Matrix3d R = box.q0.toRotationMatrix();
  const Eigen::Vector3d lowest = box.hull->Support(R.transpose() * -Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(box.p0.z() + (R * lowest).z(), 0, kTight);
  EXPECT_GT(std::abs(Eigen::AngleAxisd(box.q0).angle()), 0.3);
  EXPECT_EQ(box.v0, Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace ecpsim::engine
