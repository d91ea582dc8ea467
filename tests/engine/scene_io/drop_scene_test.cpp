#include "engine/scene_io/drop_scene.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "common/errors.h"
#include "geometry/mesh_io.h"
#include "tests/geometry/test_meshes.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// values given or a few flops from them: a few ulps of O(1) numbers
constexpr double kTight = 1e-12;

class DropSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("ecpsim_drop_{}_{}", getpid(), info->name());
    fs::create_directories(dir_);
    // the unit cube [0, 1]³, its centre of mass off the file origin
    geometry::SaveMesh(
        geometry::testing::MakeBoxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
        (dir_ / "cube.obj").string());
    options_.mesh = (dir_ / "cube.obj").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  DropOptions options_;
};

TEST_F(DropSceneTest, TheMeshStartsAboveTheGround) {
  options_.scale = 0.5;
  options_.height = 0.3;
  options_.tilt_deg = 90;
  options_.spin = 2;
  options_.duration = 0.5;
  const LoadedScene loaded = MakeDropScene(options_);
  const Scene& scene = loaded.scene;
  ASSERT_EQ(scene.bodies.size(), 1u);
  const Body& body = scene.bodies[0];
  EXPECT_EQ(body.name, "cube");
  // density 1000 kg/m³ by default; kg: the mesh's volume integral (~1e-12 relative) × 125 kg
  constexpr double kMeshMassRoundOff = 1e-10;
  EXPECT_NEAR(body.mass, 1000 * 0.125, kMeshMassRoundOff);
  EXPECT_NEAR(body.p0.z(), 0.3 + 0.25, kTight);
  EXPECT_EQ(body.w0, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(scene.duration, 0.5);
  ASSERT_EQ(scene.contacts.size(), 1u);
  EXPECT_EQ(scene.contacts[0].friction.mu, 0.22);
  EXPECT_EQ(scene.contacts[0].friction.e_r, 0.1);
  EXPECT_EQ(scene.obstacles[0].shape->Value(0, Eigen::Vector3d(0, 0, -0.5)), -0.5);
  // a 0.87 m cube: a plausible size, no warning; the default output settings
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(loaded.output.every, OutputSettings{}.every);
  EXPECT_EQ(loaded.output.fps, OutputSettings{}.fps);

  options_.mass = 2;
  EXPECT_NEAR(MakeDropScene(options_).scene.bodies[0].mass, 2, kTight);
}

TEST_F(DropSceneTest, UnitsScaleTheMeshLikeScale) {
  options_.units = "cm";
  const Scene scene = MakeDropScene(options_).scene;
  // a 1 cm cube: its lowest point 0.1 m up, its CM 0.005 m above that
  EXPECT_NEAR(scene.bodies[0].p0.z(), 0.1 + 0.005, kTight);
  constexpr double kGramRoundOff = 1e-15;  // kg: 1e-12 of the 1 g mass
  EXPECT_NEAR(scene.bodies[0].mass, 1000 * 1e-6, kGramRoundOff);
  options_.scale = 0.01;
  EXPECT_NO_THROW(MakeDropScene(options_));
  options_.scale = 0.001;
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(HasSubstr("--scale = 0.001 and --units = cm")));
}

TEST_F(DropSceneTest, AMeshOfImplausibleSizeAddsAWarningNamingTheUnits) {
  options_.scale = 100;  // a 173 m cube
  EXPECT_THAT(MakeDropScene(options_).warnings,
              ElementsAre(fmt::format("{} is 173 m across; if it is in metres use --units m (or "
                                      "--scale 1)",
                                      options_.mesh)));
}

TEST_F(DropSceneTest, OptionsOutOfRangeAreNamed) {
  options_.height = -1;
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(HasSubstr("--height = -1: expected a height >= 0 m")));
  options_.height = 0.1;
  options_.h = 0;
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(HasSubstr("--dt = 0: expected a time step > 0 s")));
  options_.h = 1e-16;
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(
                  HasSubstr("--dt = 1e-16: expected at most 4503599627370496 steps")));
  options_.h = 0.01;
  options_.mass = 1e200;
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(HasSubstr("--mass = 1e+200: expected a mass in")));
  options_.mass.reset();
  // the options are in range, the scene is not (ValidateScene): far more than 1e6 sizes of the
  // cube up, named with the scene's key
  options_.height = 1e100;
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr(fmt::format("ecpsim drop {}: bodies[0].position = [0, 0, 1e+100",
                                              options_.mesh)),
                        HasSubstr("expected body \"cube\" within 1e+06 × its size"))));
  options_.height = 0;
  options_.mesh = (dir_ / "none.stl").string();
  EXPECT_THAT([&] { MakeDropScene(options_); },
              ThrowsMessage<InputError>(HasSubstr("none.stl: no such file")));
}

}  // namespace
}  // namespace ecpsim::engine
