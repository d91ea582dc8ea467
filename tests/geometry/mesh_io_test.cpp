#include "geometry/mesh_io.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

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
                                           "box.off", "box.gltf"));

TEST(MeshIoTest, ScaleMultipliesCoordinates) {
  // millimetres to metres: a 1 × 2 × 3 mm box is 6e-9 m³
  const TriangleMesh mesh = LoadMesh(FixturePath("box.obj"), 1e-3);
  const MassProperties p = ComputeMassProperties(mesh, 1.0);
  EXPECT_NEAR(p.volume / 6e-9, 1.0, kRoundOff);
  EXPECT_LE((p.center_of_mass - Eigen::Vector3d(0.5e-3, 1e-3, 1.5e-3)).norm(), 1e-15);
}

TEST(MeshIoTest, RejectsBadScale) {
  for (double scale : {0.0, -2.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THAT([&] { LoadMesh(FixturePath("box.obj"), scale); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("box.obj"), HasSubstr("scale"))));
  }
  EXPECT_THAT([&] { LoadMesh(FixturePath("box.obj"), 1e308); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("box.obj"), HasSubstr("overflows"))));
}

struct BadInput {
  const char* file;
  const char* problem;
};

class BadFixtureTest : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadFixtureTest, ThrowsNamingFileAndProblem) {
  const std::string path = FixturePath(GetParam().file);
  EXPECT_THAT([&] { LoadMesh(path); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(path), HasSubstr(GetParam().problem))));
}

INSTANTIATE_TEST_SUITE_P(AllBadInputs, BadFixtureTest,
                         ::testing::Values(BadInput{"does_not_exist.obj", "no such mesh file"},
                                           BadInput{"empty.obj", "empty file"},
                                           BadInput{"random_bytes.stl", "cannot read the mesh"},
                                           BadInput{"points_only.obj", "no triangles"},
                                           BadInput{"line_only.obj", "no triangles"},
                                           BadInput{"nan.obj", "non-finite coordinate"}));

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
  // to ~1e-7 relative
  const TriangleMesh mesh = testing::MakePrismMesh(24, 0.3, 1.7);
  const std::string path = (folder_ / (std::string("prism") + GetParam())).string();
  SaveMesh(mesh, path);
  const TriangleMesh loaded = LoadMesh(path);
  EXPECT_EQ(loaded.vertices.size(), mesh.vertices.size());
  EXPECT_EQ(loaded.triangles.size(), mesh.triangles.size());
  const MassProperties a = ComputeMassProperties(mesh, 1.0);
  const MassProperties b = ComputeMassProperties(loaded, 1.0, path);
  EXPECT_NEAR(b.volume / a.volume, 1.0, 1e-6);
  EXPECT_LE((b.center_of_mass - a.center_of_mass).norm(), 1e-6);
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
