#include "geometry/mesh_io.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_topology.h"
#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using ::testing::AllOf;
using testing::FixturePath;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// the fixture box [0,1] × [0,2] × [0,3] has single-precision-exact corners, so every format
// must give the same volume and centre to round-off
constexpr double kRoundOff = 1e-12;

class FixtureFormatTest : public ::testing::TestWithParam<const char*> {};

TEST_P(FixtureFormatTest, LoadsTheSameClosedBox) {
  const std::string path = FixturePath(GetParam());
  const TriangleMesh mesh = LoadMesh(path);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  const MeshTopology topology = AnalyzeTopology(mesh);
  EXPECT_TRUE(topology.closed);
  EXPECT_TRUE(topology.consistently_oriented);
  const MassProperties p = ComputeMassProperties(mesh, 1.0, path);
  EXPECT_NEAR(p.volume, 6.0, kRoundOff);
  EXPECT_LE((p.center_of_mass - Eigen::Vector3d(0.5, 1.0, 1.5)).norm(), kRoundOff);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, FixtureFormatTest,
                         ::testing::Values("box.obj", "box_binary.stl", "box_ascii.stl", "box.ply",
                                           "box_binary.ply", "box.off", "box.gltf"));

TEST(MeshIoTest, ScaleMultipliesCoordinates) {
  // millimetres to metres: a 1 × 2 × 3 mm box is 6e-9 m³
  const TriangleMesh mesh = LoadMesh(FixturePath("box.obj"), 1e-3);
  const MassProperties p = ComputeMassProperties(mesh, 1.0);
  EXPECT_NEAR(p.volume / 6e-9, 1.0, kRoundOff);
  constexpr double kMillimetreRoundOff = 1e-15;  // m: ~10³ ulps of millimetre coordinates
  EXPECT_LE((p.center_of_mass - Eigen::Vector3d(0.5e-3, 1e-3, 1.5e-3)).norm(), kMillimetreRoundOff);
}

TEST(MeshIoTest, RejectsBadScale) {
  for (double scale : {0.0, -2.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THAT([&] { LoadMesh(FixturePath("box.obj"), scale); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("box.obj"), HasSubstr("scale"))));
  }
}

TEST(MeshIoTest, ScaleOutsideTheSupportedRangeIsAnInputError) {
  // the √14 m box: 1e200 used to abort in the weld (its tolerance overflowed), 1e308 overflows
  // the coordinates themselves, 1e-30 underflows the inertia (L⁵ ~ 1e-150 × density)
  for (double scale : {1e200, 1e308, 1e25, 1e-30, 1e-300}) {
    EXPECT_THAT([&] { LoadMesh(FixturePath("box.obj"), scale); },
                ThrowsMessage<InputError>(AllOf(
                    HasSubstr("box.obj: scale = "), HasSubstr("m across"),
                    HasSubstr("expected a bounding-box diagonal between 1e-20 m and 1e+20 m"))))
        << scale;
  }
}

TEST(MeshIoTest, SizesFromTheRangeEndsLoadWithExactProportions) {
  // a 0.1 mm microrobot part, a 1 km hull and both ends of the supported range: volume ∝ L³ and
  // inertia ∝ L⁵ to round-off, so every relative property is that of the 1 m box (the scales
  // are not powers of 2, so each product rounds: a few ulps, accumulated over 12 triangles)
  constexpr double kRelativeRoundOff = 1e-13;
  const MassProperties unit = ComputeMassProperties(LoadMesh(FixturePath("box.obj")), 1000.0);
  for (double scale : {1e-4, 1e3, 3e-21, 2.6e19}) {
    const std::string path = FixturePath("box.obj");
    const MassProperties p = ComputeMassProperties(LoadMesh(path, scale), 1000.0, path);
    EXPECT_NEAR(p.volume / (unit.volume * std::pow(scale, 3)), 1.0, kRelativeRoundOff) << scale;
    EXPECT_NEAR(p.mass / (unit.mass * std::pow(scale, 3)), 1.0, kRelativeRoundOff) << scale;
    EXPECT_LE((p.center_of_mass / scale - unit.center_of_mass).norm(),
              kRelativeRoundOff * unit.center_of_mass.norm())
        << scale;
    const double l5 = std::pow(scale, 5);
    EXPECT_LE((p.inertia / l5 - unit.inertia).norm(), kRelativeRoundOff * unit.inertia.norm())
        << scale;
    EXPECT_LE((p.principal_moments / l5 - unit.principal_moments).norm(),
              kRelativeRoundOff * unit.principal_moments.norm())
        << scale;
  }
}

TEST(MeshIoTest, MirroringNodeTransformKeepsTrianglesFacingOutward) {
  // two boxes, one placed by scale (−1, 1, 1): see make_fixtures.py for the closed form. Without
  // re-winding, the mirrored copy is inside out and the volumes cancel (0 m³)
  constexpr double kCornerRoundOff = 1e-12;  // exact single-precision corners, 24 triangles
  for (const char* file : {"mirrored_boxes.gltf", "mirrored_boxes.fbx"}) {
    const std::string path = FixturePath(file);
    const TriangleMesh mesh = LoadMesh(path);
    const MeshTopology topology = AnalyzeTopology(mesh);
    EXPECT_TRUE(topology.closed) << file;
    EXPECT_TRUE(topology.consistently_oriented) << file;
    const MassProperties p = ComputeMassProperties(mesh, 1.0, path);
    EXPECT_NEAR(p.volume, 12.0, kCornerRoundOff) << file;
    EXPECT_LE((p.center_of_mass - Eigen::Vector3d(0.0, 1.0, 1.5)).norm(), kCornerRoundOff) << file;
    const Eigen::Matrix3d expected = Eigen::Vector3d(13.0, 37.0, 32.0).asDiagonal();
    EXPECT_LE((p.inertia - expected).norm(), kCornerRoundOff * expected.norm()) << file;
    // each box by itself encloses +6 m³: both face outward
    for (const double volume : testing::ComponentVolumes(mesh))
      EXPECT_NEAR(volume, 6.0, kCornerRoundOff);
  }
}

TEST(MeshIoTest, CollectionFbxWithMirroredPivotsGivesASolid) {
  // assimp-testmodels' cubes_with_mirroring_and_pivot.fbx: before the re-winding its principal
  // moments came out negative and its centre of mass outside the cubes
  const std::string path = "/usr/share/assimp/models/FBX/cubes_with_mirroring_and_pivot.fbx";
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << path << " is missing: install assimp-testmodels (scripts/setup.sh)";
  }
  const TriangleMesh mesh = LoadMesh(path);
  const MassProperties p = ComputeMassProperties(mesh, 1000.0, path);
  EXPECT_GT(p.principal_moments.minCoeff(), 0.0);
  // its parts: three 0.1 m cubes, two of them placed by mirroring transforms, each +1e-3 m³
  // when facing outward (−1e-3 m³ inside out, as before), and a hollow cube, whose inner shell
  // faces into its cavity (negative) and lies inside its outer shell
  constexpr double kFloatRoundOff = 1e-6;  // relative: float corners, 0.1 m edges
  std::vector<double> volumes = testing::ComponentVolumes(mesh);
  std::sort(volumes.begin(), volumes.end());
  ASSERT_EQ(volumes.size(), 5u);
  EXPECT_LT(volumes[0], 0.0);
  EXPECT_GT(volumes[1], -volumes[0]);
  for (int cube = 2; cube < 5; ++cube) EXPECT_NEAR(volumes[cube], 1e-3, 1e-3 * kFloatRoundOff);
  EXPECT_NEAR(p.volume, std::accumulate(volumes.begin(), volumes.end(), 0.0),
              p.volume * kFloatRoundOff);
}

TEST(MeshIoTest, RejectsADirectory) {
  const std::string path = std::string(ECPSIM_SOURCE_DIR) + "/tests/fixtures";
  EXPECT_THAT([&] { LoadMesh(path); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(path), HasSubstr("not a regular file"))));
}

TEST(MeshIoTest, OpenInconsistentAndFlatMeshesLoadButHaveNoMassProperties) {
  // loading checks the file; being a solid is the business of ComputeMassProperties
  const std::string open = FixturePath("open_box.obj");
  const MeshTopology open_topology = AnalyzeTopology(LoadMesh(open));
  EXPECT_FALSE(open_topology.closed);
  EXPECT_EQ(open_topology.boundary_edges, 4);
  EXPECT_THAT([&] { ComputeMassProperties(LoadMesh(open), 1.0, open); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(open), HasSubstr("open"))));

  const std::string inconsistent = FixturePath("inconsistent_box.obj");
  EXPECT_THAT([&] { ComputeMassProperties(LoadMesh(inconsistent), 1.0, inconsistent); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr(inconsistent), HasSubstr("inconsistently oriented"))));

  const std::string flat = FixturePath("flat_tetrahedron.obj");
  EXPECT_TRUE(AnalyzeTopology(LoadMesh(flat)).closed);
  EXPECT_THAT([&] { ComputeMassProperties(LoadMesh(flat), 1.0, flat); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(flat), HasSubstr("flat"))));
}

class SaveMeshTest : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("ecpsim_mesh_io_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::filesystem::path folder_;
};

TEST_P(SaveMeshTest, RoundTripKeepsTheMesh) {
  // a 24-gon prism with non-round coordinates: single precision in the file bounds the error
  // to ~1e-7 relative, which 1e-6 covers in the volume (relative) and the 1.7 m prism's centre (m)
  constexpr double kFloatFileError = 1e-6;
  const TriangleMesh mesh = testing::MakePrismMesh(24, 0.3, 1.7);
  const std::string path = (folder_ / (std::string("prism") + GetParam())).string();
  SaveMesh(mesh, path);
  const TriangleMesh loaded = LoadMesh(path);
  EXPECT_EQ(loaded.vertices.size(), mesh.vertices.size());
  EXPECT_EQ(loaded.triangles.size(), mesh.triangles.size());
  const MassProperties a = ComputeMassProperties(mesh, 1.0);
  const MassProperties b = ComputeMassProperties(loaded, 1.0, path);
  EXPECT_NEAR(b.volume / a.volume, 1.0, kFloatFileError);
  EXPECT_LE((b.center_of_mass - a.center_of_mass).norm(), kFloatFileError);
  // only the file itself is left: the temporary was renamed
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder_)) {
    EXPECT_EQ(entry.path().filename().string(), std::string("prism") + GetParam());
    ++files;
  }
  EXPECT_EQ(files, 1);
}

INSTANTIATE_TEST_SUITE_P(AllWritableFormats, SaveMeshTest,
                         ::testing::Values(".obj", ".stl", ".ply", ".OBJ"));

TEST(MeshIoTest, SaveRejectsUnknownExtensionAndMissingFolder) {
  const TriangleMesh mesh = testing::MakeUnitTetrahedron();
  EXPECT_THAT([&] { SaveMesh(mesh, "out/tet.xyz"); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("out/tet.xyz"), HasSubstr(".xyz"))));
  const std::string missing = "/nonexistent-folder-ecpsim/tet.obj";
  EXPECT_THAT([&] { SaveMesh(mesh, missing); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(missing), HasSubstr("cannot"))));
}

}  // namespace
}  // namespace ecpsim::geometry
