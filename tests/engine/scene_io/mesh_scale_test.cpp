#include "engine/scene_io/mesh_scale.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/errors.h"
#include "engine/scene_limits.h"

namespace ecpsim::engine {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

const MeshScaleKeys kCli{"--scale", "--units"};

TEST(MeshScaleTest, UnitsAreMetresPerUnit) {
  EXPECT_EQ(MetresPerUnit("mm"), 0.001);
  EXPECT_EQ(MetresPerUnit("cm"), 0.01);
  EXPECT_EQ(MetresPerUnit("m"), 1.0);
  EXPECT_EQ(MetresPerUnit("in"), 0.0254);  // exact by definition
  EXPECT_FALSE(MetresPerUnit("ft"));
  EXPECT_FALSE(MetresPerUnit("MM"));
}

TEST(MeshScaleTest, ScaleAndUnitsResolveToOneFactor) {
  EXPECT_EQ(ResolveMeshScale(std::nullopt, std::nullopt, kCli), 1.0);
  EXPECT_EQ(ResolveMeshScale(0.5, std::nullopt, kCli), 0.5);
  EXPECT_EQ(ResolveMeshScale(std::nullopt, std::string("mm"), kCli), 0.001);
  // the same factor typed two ways agrees
  EXPECT_EQ(ResolveMeshScale(25.4e-3, std::string("in"), kCli), 0.0254);
  EXPECT_THAT([] { ResolveMeshScale(0.01, std::string("mm"), kCli); },
              ThrowsMessage<InputError>(
                  HasSubstr("--scale = 0.01 and --units = mm (0.001 m per unit) disagree")));
  EXPECT_THAT([] { ResolveMeshScale(std::nullopt, std::string("ft"), kCli); },
              ThrowsMessage<InputError>(HasSubstr("--units = ft: expected one of mm, cm, m, in")));
  EXPECT_THAT([] { ResolveMeshScale(1e200, std::nullopt, kCli); },
              ThrowsMessage<InputError>(HasSubstr("--scale = 1e+200: expected a scale in")));
}

TEST(MeshScaleTest, MeshAcrossIsTheBoundingBoxDiagonal) {
  geometry::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  EXPECT_DOUBLE_EQ(MeshAcross(mesh), std::sqrt(14.0));
  EXPECT_EQ(MeshAcross(geometry::TriangleMesh{}), 0);
}

TEST(MeshScaleTest, PlausibleSizesGiveNoWarning) {
  EXPECT_EQ(MeshSizeWarning("part.stl", 0.5, 1, kCli), "");
  EXPECT_EQ(MeshSizeWarning("part.stl", kMinPlausibleMeshSize, 1, kCli), "");
  EXPECT_EQ(MeshSizeWarning("part.stl", kMaxPlausibleMeshSize, 1, kCli), "");
}

TEST(MeshScaleTest, WarningsNameTheSizeAndAUnitThatFits) {
  // a 0.254 m part written in millimetres and read as metres
  EXPECT_EQ(MeshSizeWarning("meshes/part.stl", 254, 1, kCli),
            "meshes/part.stl is 254 m across; if it is in millimetres use --units mm (or "
            "--scale 0.001)");
  // a part in metres read as millimetres
  EXPECT_EQ(MeshSizeWarning("part.obj", 0.000919, 0.001, kCli),
            "part.obj is 0.919 mm across; if it is in metres use --units m (or --scale 1)");
  // scaled up by mistake: dropping the scale is the first suggestion
  EXPECT_EQ(MeshSizeWarning("part.obj", 919, 1000, kCli),
            "part.obj is 919 m across; if it is in metres use --units m (or --scale 1)");
  // in a scene the keys are spelt as YAML
  EXPECT_EQ(MeshSizeWarning("meshes/part.stl", 254, 1, {"bodies[0].scale", "bodies[0].units"}),
            "meshes/part.stl is 254 m across; if it is in millimetres use bodies[0].units: mm "
            "(or bodies[0].scale: 0.001)");
  // no unit makes a 40 km mesh plausible
  EXPECT_EQ(MeshSizeWarning("city.obj", 4e4, 1, kCli),
            "city.obj is 4e+04 m across; check its unit (--units or --scale)");
}

}  // namespace
}  // namespace ecpsim::engine
