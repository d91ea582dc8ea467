// Bodies made of convex parts touching bodies (engine/README.md, "Bodies made of convex parts"):
// scenes/cube_in_cup.yaml and scenes/peg_in_hole.yaml against their geometry, a peg pushed by a
// finger and sliding down the wall of its hole against Coulomb's law, and the scene's contacts and
// their combined output.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/report/contact_groups.h"
#include "engine/report/penetration.h"
#include "engine/report/trajectory_columns.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// m: the bar for where a body comes to rest on a part (floor heights to 1e-9 m) and for
// overlap between parts. The gap rows converge to the solver's tolerance (1e-12) in the
// contact's length (0.04 m) plus the coordinates' round-off (ulps of 0.1 m), so a correct rest
// meets it by three orders; a contact with the hull instead of the parts misses it by centimetres
constexpr double kRestTolerance = 1e-9;
// m/s: a body at rest moves no faster than this: 1e-9 m over the last step (h = 0.005 s)
constexpr double kRestSpeed = 1e-9 / 0.005;

std::string ScenePath(const std::string& name) {
  return std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + name;
}

// the deepest overlap of any part pair, body or obstacle over a whole run of `scene`
struct RunEnd {
  State state;
  double deepest = 0;
};

RunEnd RunToEnd(const Scene& scene) {
  RunEnd run{InitialState(scene)};
  const PenetrationProbe probe(scene);
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  for (int k = 0; k < steps; ++k) {
    const StepReport report = Step(scene, run.state);
    EXPECT_TRUE(report.converged) << "t = " << run.state.t;
    run.deepest = std::max(run.deepest, probe.MaxDepth(scene, run.state));
  }
  return run;
}

// rad: the body's turn from upright (its z axis against the world's), of its z, x or y axis
// whichever is most nearly vertical (a cube may come to rest on any face)
double TiltFromAFace(const BodyState& body) {
  double best = INFINITY;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d u = body.Q_WB * Eigen::Vector3d::Unit(axis);
    best = std::min(best, std::acos(std::min(1.0, std::abs(u.z()))));
  }
  return best;
}

TEST(PartContactsTest, CubeDroppedIntoACupRestsOnItsFloor) {
  const Scene scene = LoadScene(ScenePath("cube_in_cup.yaml")).scene;
  const RunEnd run = RunToEnd(scene);
  const BodyState& cube = run.state.bodies[1];
  // the floor's top at 0.01 m, the cube's half edge 0.02 m: on a face, flat
  EXPECT_NEAR(cube.p_WB.z(), 0.03, kRestTolerance);
  EXPECT_LE(TiltFromAFace(cube), kRestTolerance / 0.02);
  EXPECT_LE(cube.v_WB.norm(), kRestSpeed);
  // inside the cavity (0.08 m across, the cube's half diagonal across it ≤ 0.0283 m)
  EXPECT_LE(std::abs(cube.p_WB.x()), 0.04 - 0.02);
  EXPECT_LE(std::abs(cube.p_WB.y()), 0.04 - 0.02);
  EXPECT_LE(run.deepest, kRestTolerance);
  // it carries the cube's weight through the floor's part only
  const double weight = scene.bodies[1].mass * 9.8;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (!pair.WithBody()) continue;
    const double force = run.state.contacts[k].p_n / scene.h;
    EXPECT_NEAR(force, pair.part == 0 ? weight : 0.0, 1e-9 * weight) << "part " << pair.part;
  }
}

// the cup of scenes/cube_in_cup.yaml and its cube, the cup's mesh copied into a folder of its own
// (a decomposition is cached beside the mesh) and decomposed by the loader
class DecomposedCupTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("ecpsim_decomposed_cup_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    std::filesystem::copy_file(ScenePath("meshes/cup.obj"), dir_ / "cup.obj");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // `extra`: more keys of the cup's body
  LoadedScene Load(const std::string& extra = "") const {
    const std::string cup =
        "  - {name: cup, mesh: cup.obj, mass: 0.3, on_ground: true, position: [0, 0], "
        "decomposition: auto" +
        extra + "}\n";
    const std::string yaml =
        "h: 0.005\nduration: 1\nground: {friction: {mu: 0.5, e_r: 0.02}}\nbodies:\n" + cup +
        "  - {name: cube, shape: {box: {size: [0.04, 0.04, 0.04]}}, mass: 0.05, "
        "position: [0.005, -0.004, 0.12], rpy: [12, 8, 25]}\n";
    return LoadSceneText(yaml, "cup_auto.yaml", dir_.string());
  }
  // the files beside the mesh that hold its decomposition
  std::vector<std::filesystem::path> CacheFiles() const {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir_))
      if (entry.path().filename().string().rfind("cup.obj.parts-", 0) == 0)
        files.push_back(entry.path());
    return files;
  }

  std::filesystem::path dir_;
};

TEST_F(DecomposedCupTest, HoldsTheCubeOnItsFloor) {
  // the cup's mesh with `decomposition: auto` instead of listed parts: its exact convex pieces,
  // each seam moved inside a part; its lid the cup's opening
  const LoadedScene loaded = Load();
  EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.bodies[0].decomposition, Decomposition::kAuto);
  EXPECT_GE(scene.bodies[0].parts.size(), 5u);
  EXPECT_EQ(scene.bodies[0].lids.size(), 1u);
  const RunEnd run = RunToEnd(scene);
  EXPECT_NEAR(run.state.bodies[1].p_WB.z(), 0.03, kRestTolerance);
  EXPECT_LE(TiltFromAFace(run.state.bodies[1]), kRestTolerance / 0.02);
  EXPECT_LE(run.deepest, kRestTolerance);
}

TEST_F(DecomposedCupTest, IsComputedOnceAndReadFromBesideTheMesh) {
  const Scene first = Load().scene;
  ASSERT_EQ(CacheFiles().size(), 1u);
  const std::filesystem::path cache = CacheFiles().front();
  const auto written = std::filesystem::last_write_time(cache);
  // read back: the same parts to the bit, the file untouched
  const Scene second = Load().scene;
  EXPECT_EQ(std::filesystem::last_write_time(cache), written);
  ASSERT_EQ(second.bodies[0].parts.size(), first.bodies[0].parts.size());
  for (size_t i = 0; i < first.bodies[0].parts.size(); ++i) {
    const auto& a = first.bodies[0].parts[i]->AsPolyhedron()->hull();
    const auto& b = second.bodies[0].parts[i]->AsPolyhedron()->hull();
    EXPECT_EQ(a.vertices, b.vertices) << "part " << i;
    EXPECT_EQ(a.normals, b.normals) << "part " << i;
    EXPECT_EQ(a.offsets, b.offsets) << "part " << i;
  }
  // a cache that is not one is computed again and rewritten
  std::ofstream(cache) << "ecpsim convex parts 1\npart 3\n0 0 0\n";
  EXPECT_EQ(Load().scene.bodies[0].parts.size(), first.bodies[0].parts.size());
  std::ifstream rewritten(cache);
  std::string header, part;
  std::getline(rewritten, header);
  std::getline(rewritten, part);
  EXPECT_NE(part, "part 3");
}

TEST_F(DecomposedCupTest, ACacheItCannotWriteLeavesAWarning) {
  // a folder where the cache file would go: the parts are computed and used, and said uncached
  Load();
  ASSERT_EQ(CacheFiles().size(), 1u);
  const std::filesystem::path cache = CacheFiles().front();
  std::filesystem::remove(cache);
  std::filesystem::create_directory(cache);
  const LoadedScene loaded = Load();
  EXPECT_GE(loaded.scene.bodies[0].parts.size(), 5u);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("its convex parts are not cached"), std::string::npos)
      << loaded.warnings[0];
}

TEST_F(DecomposedCupTest, EachToleranceHasACacheOfItsOwn) {
  const Scene exact = Load().scene;
  ASSERT_EQ(CacheFiles().size(), 1u);
  const Scene approximate = Load(", decomposition_tolerance: 0.001").scene;
  EXPECT_EQ(CacheFiles().size(), 2u);
  // the cup's exact parts overlap nowhere and fill it, so merging any two would fill a corner of
  // its cavity, centimetres deep: the tolerance changes nothing
  ASSERT_EQ(approximate.bodies[0].parts.size(), exact.bodies[0].parts.size());
  for (size_t i = 0; i < exact.bodies[0].parts.size(); ++i) {
    EXPECT_EQ(approximate.bodies[0].parts[i]->AsPolyhedron()->hull().vertices,
              exact.bodies[0].parts[i]->AsPolyhedron()->hull().vertices)
        << "part " << i;
  }
}

TEST_F(DecomposedCupTest, AToleranceOutOfRangeOrWithoutAMeshIsAnError) {
  for (const char* value : {"-0.001", "1", ".nan", "[0.1]"}) {
    try {
      Load(fmt::format(", decomposition_tolerance: {}", value));
      FAIL() << "expected an InputError for " << value;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bodies[0].decomposition_tolerance"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("a tolerance >= 0 and < 1"), std::string::npos)
          << e.what();
    }
  }
  const std::string yaml =
      "duration: 1\nground: {}\nbodies:\n"
      "  - {name: a, shape: {box: {size: [0.1, 0.1, 0.1]}}, mass: 1, on_ground: true, "
      "decomposition_tolerance: 0.01}\n";
  try {
    LoadSceneText(yaml, "t.yaml", dir_.string());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("only on a body with a `mesh`"), std::string::npos)
        << e.what();
  }
}

TEST(PartContactsTest, AToleranceBesideListedPartsIsUnusedAndSaysSo) {
  const LoadedScene loaded =
      LoadScene(ScenePath("cube_in_cup.yaml"), {"bodies.0.decomposition_tolerance=0.01"});
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings.front().find("bodies[0].decomposition_tolerance: unused, the body "
                                         "lists its `parts`"),
            std::string::npos)
      << loaded.warnings.front();
}

TEST(PartContactsTest, AConvexMeshDecomposedKeepsItsHull) {
  const std::string box =
      "duration: 1\nground: {}\nbodies:\n"
      "  - {name: b, mesh: " +
      std::string(ECPSIM_SOURCE_DIR) +
      "/tests/fixtures/meshes/box.obj, mass: 1, on_ground: true, decomposition: auto}\n";
  const Scene convex = LoadSceneText(box, "box_auto.yaml", ".").scene;
  EXPECT_EQ(convex.bodies[0].decomposition, Decomposition::kNone);
  EXPECT_TRUE(convex.bodies[0].parts.empty());
}

// scenes/cube_in_mug.yaml's cube, dropped into the mug of `scene`, at rest on its floor: the
// floor's top at 0.01 m, the cube's half edge 0.015 m, on a face, flat
void ExpectTheCubeRestsOnTheMugsFloor(const Scene& scene) {
  const RunEnd run = RunToEnd(scene);
  const BodyState& cube = run.state.bodies[1];
  EXPECT_NEAR(cube.p_WB.z(), 0.025, kRestTolerance);
  EXPECT_LE(TiltFromAFace(cube), kRestTolerance / 0.015);
  EXPECT_LE(cube.v_WB.norm(), kRestSpeed);
  EXPECT_LE(run.deepest, kRestTolerance);
}

TEST(PartContactsTest, CubeDroppedIntoAMugRestsOnItsFloor) {
  // scenes/cube_in_mug.yaml: the mug's parts decomposed from its mesh by the loader
  const LoadedScene loaded = LoadScene(ScenePath("cube_in_mug.yaml"));
  EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  EXPECT_EQ(loaded.scene.bodies[0].parts.size(), 8u);  // its exact pieces, none merged
  ExpectTheCubeRestsOnTheMugsFloor(loaded.scene);
}

TEST(PartContactsTest, CubeDroppedIntoARoundMugRestsOnItsFloor) {
  // scenes/cube_in_mug.yaml with the round mug of scripts/round_mug.py: a 32-gon whose inside
  // the exact pieces follow one facet each
  const Scene scene =
      LoadScene(ScenePath("cube_in_mug.yaml"), {"bodies.0.mesh=meshes/round_mug.obj"}).scene;
  EXPECT_EQ(scene.bodies[0].parts.size(), 36u);
  ExpectTheCubeRestsOnTheMugsFloor(scene);
}

TEST(PartContactsTest, AFirstLoadAndACachedOneGiveTheSameParts) {
  // the round mug's parts, computed (no cache beside its mesh) and then read from the cache:
  // the hull of a grown part's corners orders its faces otherwise than the decomposition's hull
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "ecpsim_round_mug_cache";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(ScenePath("meshes/round_mug.obj"), dir / "round_mug.obj");
  const std::string yaml =
      "duration: 1\nground: {}\nbodies:\n  - {name: mug, mesh: round_mug.obj, mass: 0.3, "
      "on_ground: true, "
      "position: [0, 0], decomposition: auto}\n";
  const Scene computed = LoadSceneText(yaml, "mug.yaml", dir.string()).scene;
  const Scene cached = LoadSceneText(yaml, "mug.yaml", dir.string()).scene;
  std::filesystem::remove_all(dir);
  ASSERT_EQ(computed.bodies[0].parts.size(), cached.bodies[0].parts.size());
  for (size_t i = 0; i < computed.bodies[0].parts.size(); ++i) {
    const geometry::ConvexHull& a = computed.bodies[0].parts[i]->AsPolyhedron()->hull();
    const geometry::ConvexHull& b = cached.bodies[0].parts[i]->AsPolyhedron()->hull();
    EXPECT_EQ(a.vertices, b.vertices) << "part " << i;
    EXPECT_EQ(a.faces, b.faces) << "part " << i;
    EXPECT_EQ(a.normals, b.normals) << "part " << i;
    EXPECT_EQ(a.offsets, b.offsets) << "part " << i;
  }
}

TEST(PartContactsTest, CubeDroppedOnTheDumbbellsBarRestsOnIt) {
  // scenes/cube_on_dumbbell.yaml: the dumbbell's exact parts
  const LoadedScene loaded = LoadScene(ScenePath("cube_on_dumbbell.yaml"));
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.bodies[0].parts.size(), 3u);  // its discs and its bar
  const RunEnd run = RunToEnd(scene);
  const BodyState& cube = run.state.bodies[1];
  // on the bar's top facet: the disc's and the bar's 96-gons' inner radii above the ground, and
  // the cube's half edge (the mesh's single-precision floats move it by ~1e-8 m)
  const double inner = std::cos(M_PI / 96);
  EXPECT_NEAR(cube.p_WB.z(), 0.1 * inner + 0.05 * inner + 0.015, 1e-7);
  EXPECT_LE(TiltFromAFace(cube), 1e-6);
  EXPECT_LE(cube.v_WB.norm(), kRestSpeed);
  // with its hull the dumbbell would hold the cube on the discs' rims
  const Scene hull =
      LoadScene(ScenePath("cube_on_dumbbell.yaml"), {"bodies.0.decomposition=none"}).scene;
  EXPECT_NEAR(RunToEnd(hull).state.bodies[1].p_WB.z(), 2 * 0.1 * inner + 0.015, 1e-7);
}

TEST(PartContactsTest, TheCupsHullWouldHoldTheCubeOnItsRim) {
  // what the parts change: with `decomposition: none` the cup touches with its hull, a solid box
  const Scene scene =
      LoadScene(ScenePath("cube_in_cup.yaml"), {"bodies.0.decomposition=none"}).scene;
  ASSERT_EQ(scene.contacts.size(), 3u);  // cup–ground, cube–ground, cup–cube
  const RunEnd run = RunToEnd(scene);
  // the hull's top at 0.08 m (the mesh's single-precision floats move it by 1e-8 m)
  EXPECT_NEAR(run.state.bodies[1].p_WB.z(), 0.10, 1e-8);
}

TEST(PartContactsTest, TheFingerPushesThePegOntoTheHolesWall) {
  // the kinematic finger moves +x at 0.02 m/s for 0.025 s, then away; the peg keeps its speed
  // until its +x face meets the wall (1 mm) at 0.05 s, falling meanwhile
  const Scene scene = LoadScene(ScenePath("peg_in_hole.yaml")).scene;
  constexpr double kFingerSpeed = 0.02;  // m/s: 0.5 mm in 0.025 s
  State state = InitialState(scene);
  double farthest = -INFINITY;
  for (int k = 1; k <= 12; ++k) {  // to 0.06 s
    ASSERT_TRUE(Step(scene, state).converged) << "step " << k;
    const BodyState& peg = state.bodies[1];
    // rigid, no slip along the push: the finger's speed, to the rows' 1e-12 convergence
    if (k <= 10) {
      EXPECT_NEAR(peg.v_WB.x(), kFingerSpeed, 1e-9 * kFingerSpeed) << "step " << k;
    }
    farthest = std::max(farthest, peg.p_WB.x());
  }
  // the peg's +x face on the wall (its centre 1 mm off the axis), no further than its tilt allows
  EXPECT_GE(farthest, 0.001 - kRestTolerance);
  EXPECT_LE(farthest, 0.0011);
}

TEST(PartContactsTest, PegFallsIntoItsHoleAndStandsOnTheTable) {
  const Scene scene = LoadScene(ScenePath("peg_in_hole.yaml")).scene;
  const RunEnd run = RunToEnd(scene);
  const BodyState& peg = run.state.bodies[1];
  EXPECT_NEAR(peg.p_WB.z(), 0.04, kRestTolerance);  // its half length above the table
  EXPECT_LE(TiltFromAFace(peg), kRestTolerance / 0.04);
  EXPECT_LE(peg.v_WB.norm(), kRestSpeed);
  // within the hole: 1 mm of clearance a side
  EXPECT_LE(std::abs(peg.p_WB.x()), 0.001 + kRestTolerance);
  EXPECT_LE(std::abs(peg.p_WB.y()), 0.001 + kRestTolerance);
  EXPECT_LE(run.deepest, kRestTolerance);
}

TEST(PartContactsTest, PegPressedOnTheHolesWallSlidesDownAtCoulombsRate) {
  // the peg against the +x wall (its centre 1 mm off the axis), its bottom 5 mm above the table,
  // pressed on the wall by F at its CM: the wall's normal force is F, its friction μ F upward
  // while the peg slides, so v_z(k h) = −k h (g − μ F / m) exactly in the implicit step. The
  // block is held fixed (kinematic, its parts as in the scene): on the table, a dynamic block
  // pushed by F sticks with the sticking creep (engine/README.md, "Sticking between bodies"),
  // 3.7e-7 m/s, whose momentum the first step's p_n pays
  constexpr double kForce = 1;  // N: μ F = 0.3 N below the weight 0.49 N, so it slides
  const std::string fixed_block =
      "bodies.0={name: block, mesh: meshes/block_with_hole.obj, kinematic: true, "
      "motion: {velocity: {position: [0, 0, 0.025], linear: [0, 0, 0]}}, parts: "
      "[{box: {size: [0.039, 0.10, 0.05]}, at: [-0.0305, 0, 0.025]}, "
      "{box: {size: [0.039, 0.10, 0.05]}, at: [0.0305, 0, 0.025]}, "
      "{box: {size: [0.032, 0.039, 0.05]}, at: [0, -0.0305, 0.025]}, "
      "{box: {size: [0.032, 0.039, 0.05]}, at: [0, 0.0305, 0.025]}]}";
  const Scene scene =
      LoadScene(ScenePath("peg_in_hole.yaml"),
                {fixed_block, "bodies.1.position=[0.001, 0, 0.045]", "bodies.1.velocity=[0, 0, 0]",
                 "loads=[{body: peg, force: [1, 0, 0]}]", "duration=0.04"})
          .scene;
  const double mu = scene.contacts.back().friction.mu, m = scene.bodies[1].mass, g = 9.8;
  EXPECT_NEAR(mu, 0.3, 1e-15);  // the pair's: the geometric mean of the bodies' (the ground's)
  State state = InitialState(scene);
  for (int k = 1; k <= 8; ++k) {  // 0.04 s: it falls 3 mm, still above the table
    ASSERT_TRUE(Step(scene, state).converged);
    const double expected = -k * scene.h * (g - mu * kForce / m);
    // the friction rows converge to 1e-12 of the contact's impulse scale: 1e-10 of the speed
    EXPECT_NEAR(state.bodies[1].v_WB.z(), expected, 1e-10 * std::abs(expected)) << "step " << k;
    EXPECT_NEAR(state.bodies[1].p_WB.x(), 0.001, kRestTolerance) << "step " << k;
  }
}

TEST(PartContactsTest, ACubeRestsOnTwoCylindricalRails) {
  // a rack: a base slab and two rails, cylinders turned to lie along x, 6 cm apart, their tops
  // 5 cm above the table; its hull reaches 7 cm. A 6 cm cube dropped on the rails rests on both
  const std::string yaml =
      "duration: 0.6\nh: 0.005\nground: {friction: {mu: 0.5, e_r: 0.01}}\nbodies:\n"
      "  - name: rack\n"
      "    shape: {box: {size: [0.2, 0.1, 0.07]}}\n"
      "    mass: 1\n"
      "    position: [0, 0, 0.035]\n"
      "    parts:\n"
      "      - {box: {size: [0.2, 0.1, 0.01]}, at: [0, 0, -0.03]}\n"
      "      - {cylinder: {radius: 0.01, length: 0.2}, at: [0, -0.03, 0.005], rpy: [0, 90, 0]}\n"
      "      - {cylinder: {radius: 0.01, length: 0.2}, at: [0, 0.03, 0.005], rpy: [0, 90, 0]}\n"
      "  - {name: cube, shape: {box: {size: [0.06, 0.06, 0.06]}}, mass: 0.1, "
      "position: [0, 0, 0.12]}\n";
  const Scene scene = LoadSceneText(yaml, "rails.yaml", ".").scene;
  const RunEnd run = RunToEnd(scene);
  EXPECT_NEAR(run.state.bodies[1].p_WB.z(), 0.05 + 0.03, kRestTolerance);
  EXPECT_LE(run.state.bodies[1].v_WB.norm(), kRestSpeed);
  EXPECT_LE(run.deepest, kRestTolerance);
  // the weight on the two rails (parts 1 and 2), split evenly by symmetry
  const double weight = scene.bodies[1].mass * 9.8 * scene.h;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (!pair.WithBody()) continue;
    EXPECT_NEAR(run.state.contacts[k].p_n, pair.part == 0 ? 0.0 : weight / 2, 1e-9 * weight)
        << "part " << pair.part;
  }
}

TEST(PartContactsTest, AHookLiftsAMugByItsHandle) {
  // scenes/hook.yaml: the hook's tip rises under the handle's top arm from 0.2 s to 1.7 s and
  // holds; the mug tilts up about its far edge, leaves the table and swings below the tip, which
  // sits in the corner of the arm and the grip
  const Scene scene = LoadScene(ScenePath("hook.yaml")).scene;
  const int mug = 0;
  const double m = scene.bodies[mug].mass, g = 9.8;
  const PenetrationProbe probe(scene);
  State state = InitialState(scene);
  const double z0 = state.bodies[mug].p_WB.z();
  double deepest = 0, energy_held = 0;
  const auto energy = [&] {
    const BodyState& s = state.bodies[mug];
    const Eigen::Matrix3d R = s.Q_WB.toRotationMatrix();
    return 0.5 * m * s.v_WB.squaredNorm() +
           0.5 * s.w_WB.dot(R * scene.bodies[mug].inertia * R.transpose() * s.w_WB) +
           m * g * s.p_WB.z();
  };
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  for (int k = 1; k <= steps; ++k) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    deepest = std::max(deepest, probe.MaxDepth(scene, state));
    if (state.t < 1.8 - 1e-9) continue;
    if (energy_held == 0) energy_held = energy();
    for (size_t c = 0; c < scene.contacts.size(); ++c) {
      const ContactPair& pair = scene.contacts[c];
      const double p_n = state.contacts[c].p_n;
      // off the table, held by the handle's parts alone: its arms and grip, 5–7 (its weight's
      // impulse is 0.015 N·s a step)
      if (!pair.WithBody() || pair.part < 5) {
        EXPECT_LE(p_n, 1e-12 * m * g * scene.h) << "t = " << state.t << ", part " << pair.part;
      }
    }
  }
  EXPECT_LE(deepest, kRestTolerance);
  // lifted: the hook rose 0.15 m, the mug's centre (which hangs below the arm) 0.1 m
  EXPECT_GT(state.bodies[mug].p_WB.z() - z0, 0.09);
  // it hangs below the tip, whose top is at 0.2 m
  EXPECT_LT(state.bodies[mug].p_WB.z(), 0.2);
  // and swings without gaining energy (the implicit step only dissipates)
  EXPECT_LE(energy(), energy_held);
}

// a bar of two box parts on the ground, reaching 5 mm into each other across x = 0 (or, with
// `overlap` 0, meeting face to face there), and a cube at `cube_z` over their middle
LoadedScene BarAndCube(double cube_z, const std::string& decomposition = "parts",
                       double overlap = 0.005) {
  const double length = 0.1 + overlap, centre = 0.05 - overlap / 2;
  const std::string yaml = fmt::format(
      "duration: 1\nground: {{friction: {{mu: 0.5}}}}\nbodies:\n"
      "  - name: bar\n"
      "    shape: {{box: {{size: [0.2, 0.1, 0.1]}}}}\n"
      "    mass: 2\n"
      "    position: [0, 0, 0.05]\n"
      "    parts: [{{box: {{size: [{0}, 0.1, 0.1]}}, at: [{1}, 0, 0]}},\n"
      "            {{box: {{size: [{0}, 0.1, 0.1]}}, at: [{2}, 0, 0]}}]\n"
      "    decomposition: {3}\n"
      "  - {{name: cube, shape: {{box: {{size: [0.1, 0.1, 0.1]}}}}, mass: 1, position: [0, 0, "
      "{4}]}}\n",
      length, -centre, centre, decomposition, cube_z);
  return LoadSceneText(yaml, "bar_and_cube.yaml", ".");
}

TEST(PartContactsTest, ABodyOfPartsTouchesABodyThroughEachPart) {
  const Scene scene = BarAndCube(0.2).scene;
  // bar–ground (a half-space: the hull), cube–ground, then bar part 0 and 1 against the cube
  ASSERT_EQ(scene.contacts.size(), 4u);
  EXPECT_EQ(scene.contacts[2].part, 0);
  EXPECT_EQ(scene.contacts[3].part, 1);
  EXPECT_EQ(scene.contacts[3].other_part, -1);
  EXPECT_EQ(&ShapeOfBody(scene, scene.contacts[3]), scene.bodies[0].parts[1].get());
  EXPECT_EQ(&ShapeOfOther(scene, scene.contacts[3]), scene.bodies[1].hull.get());
  // trajectory.csv reports the pair once
  const std::vector<ContactGroup> groups = ContactGroups(scene);
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_EQ(groups[2].first, 2);
  EXPECT_EQ(groups[2].end, 4);
  const std::vector<std::string> columns = TrajectoryColumns(scene);
  EXPECT_EQ(std::count(columns.begin(), columns.end(), "bar.cube.pn"), 1);
  // with `decomposition: none` the bar touches with its hull
  const Scene hull = BarAndCube(0.2, "none").scene;
  EXPECT_EQ(hull.contacts.size(), 3u);
  EXPECT_EQ(hull.contacts[2].part, -1);
}

TEST(PartContactsTest, PartsThatMeetFaceToFaceAreNamedInAWarning) {
  EXPECT_TRUE(BarAndCube(0.2).warnings.empty());
  const std::vector<std::string> warnings = BarAndCube(0.2, "parts", 0).warnings;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("bodies[0].parts: parts 0 and 1 meet face to face"), std::string::npos)
      << warnings[0];
  // (at the seam's face, x = 0 in the bar's frame)
  EXPECT_NE(warnings[0].find("centred at (0, 0, 0) m"), std::string::npos) << warnings[0];
  // the hull's contacts do not touch the parts
  EXPECT_TRUE(BarAndCube(0.2, "none", 0).warnings.empty());
}

TEST(PartContactsTest, TheCubeOnTheBarRestsOnBothParts) {
  // the cube centred over the parts' overlap: the two carry its weight together
  const Scene scene = BarAndCube(0.15).scene;
  State state = InitialState(scene);
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(Step(scene, state).converged);
  const double weight = scene.bodies[1].mass * 9.8 * scene.h;
  EXPECT_NEAR(state.contacts[2].p_n + state.contacts[3].p_n, weight, 1e-12 * weight);
  EXPECT_NEAR(state.bodies[1].p_WB.z(), 0.15, kRestTolerance);
  // the combined contact: the sum, at the pressure's centre (x = 0 by symmetry of the loads'
  // sum, whichever split the step took)
  const ContactState combined = CombinedContact(state, ContactGroups(scene)[2]);
  EXPECT_NEAR(combined.p_n, weight, 1e-12 * weight);
}

TEST(PartContactsTest, CombinedContactKeepsTheTotalForceAndMoment) {
  // two members with different normals (a cube on a floor against a wall)
  State state;
  state.contacts.resize(2);
  ContactState& floor = state.contacts[0];
  floor.a1 = Eigen::Vector3d(0.01, 0.02, 0.01);
  floor.p_n = 3;
  floor.p_t = 0.4;
  floor.p_o = -0.2;
  floor.p_r = 0.01;
  floor.sigma = 0.5;
  ContactState& wall = state.contacts[1];
  wall.n = Eigen::Vector3d::UnitX();
  wall.t = Eigen::Vector3d::UnitY();
  wall.o = Eigen::Vector3d::UnitZ();
  wall.a1 = Eigen::Vector3d(-0.04, 0, 0.03);
  wall.p_n = 1;
  wall.p_t = 0.1;
  wall.p_o = 0.3;
  wall.sigma = 0.1;
  const ContactState c = CombinedContact(state, {0, 2});
  const auto force = [](const ContactState& s) {
    return Eigen::Vector3d(s.n * s.p_n + s.t * s.p_t + s.o * s.p_o);
  };
  EXPECT_TRUE((force(c) - (force(floor) + force(wall))).norm() < 1e-15);
  EXPECT_EQ(c.n, floor.n);  // the frame of the member carrying more
  EXPECT_TRUE((c.a1 - (3 * floor.a1 + wall.a1) / 4).norm() < 1e-16);
  EXPECT_NEAR(c.sigma, (3 * 0.5 + 0.1) / 4, 1e-16);
  const Eigen::Vector3d moment = (floor.a1 - c.a1).cross(force(floor)) + floor.n * floor.p_r +
                                 (wall.a1 - c.a1).cross(force(wall)) + wall.n * wall.p_r;
  EXPECT_NEAR(c.p_r, c.n.dot(moment), 1e-16);
  // a group of one is its contact
  const ContactState one = CombinedContact(state, {1, 2});
  EXPECT_EQ(one.a1, wall.a1);
  EXPECT_EQ(one.p_o, wall.p_o);
  EXPECT_EQ(one.n, wall.n);
}

TEST(PartContactsTest, ContactsNamingPartsAreChecked) {
  const Scene scene = BarAndCube(0.2).scene;
  Scene bad = scene;
  bad.contacts[3].part = 2;
  EXPECT_THROW(ValidateScene(bad), SceneError);
  bad = scene;
  bad.contacts[2].other_part = 0;  // the cube has no parts
  EXPECT_THROW(ValidateScene(bad), SceneError);
  bad = scene;
  bad.contacts[3].part = 0;  // the pair of parts twice
  EXPECT_THROW(ValidateScene(bad), SceneError);
  bad = scene;
  std::swap(bad.contacts[1], bad.contacts[2]);  // the bar–cube contacts apart
  EXPECT_THROW(ValidateScene(bad), SceneError);
}

TEST(PartContactsTest, DecompositionPartsNeedsParts) {
  const std::string yaml =
      "duration: 1\nground: {}\nbodies:\n"
      "  - {name: a, shape: {box: {size: [0.1, 0.1, 0.1]}}, mass: 1, decomposition: parts}\n";
  try {
    LoadSceneText(yaml, "t.yaml", ".");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].decomposition"), std::string::npos) << e.what();
  }
  const std::string wrong =
      "duration: 1\nground: {}\nbodies:\n"
      "  - {name: a, shape: {box: {size: [0.1, 0.1, 0.1]}}, mass: 1, decomposition: some}\n";
  try {
    LoadSceneText(wrong, "t.yaml", ".");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("one of none, parts, auto"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ecpsim::engine
