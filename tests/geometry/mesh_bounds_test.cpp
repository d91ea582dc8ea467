#include "geometry/mesh_bounds.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tolerances.h"

namespace ecpsim::geometry {
namespace {

TEST(MeshBoundsTest, BoxBoundsDiagonalAndLargestCoordinate) {
  const std::vector<Eigen::Vector3d> vertices = {{1, -2, 3}, {-4, 5, 0}, {0, 0, -6}};
  const MeshBounds bounds = ComputeMeshBounds(vertices);
  EXPECT_EQ(bounds.lo, Eigen::Vector3d(-4, -2, -6));
  EXPECT_EQ(bounds.hi, Eigen::Vector3d(1, 5, 3));
  // extents 5, 7, 9: √155, to a few ulps of its 12.4
  constexpr double kDiagonalRoundOff = 1e-14;
  EXPECT_NEAR(bounds.diagonal, std::sqrt(155.0), kDiagonalRoundOff);
  EXPECT_EQ(bounds.max_abs, 6.0);
  EXPECT_EQ(ComputeMeshBounds({}).diagonal, 0.0);
}

TEST(MeshBoundsTest, DiagonalNeitherOverflowsNorUnderflows) {
  // squaring 1e200 overflows and squaring 1e-200 underflows; the diagonal must not
  for (double size : {1e200, 1e-200}) {
    const MeshBounds bounds = ComputeMeshBounds({{0, 0, 0}, {size, size, size}});
    EXPECT_NEAR(bounds.diagonal / size, std::sqrt(3.0), kUnitRoundOff) << size;
  }
}

TEST(MeshBoundsTest, SupportedRangeIsInclusiveAndCoversCoordinates) {
  MeshBounds bounds;
  bounds.diagonal = kMinMeshSize;
  bounds.max_abs = kMinMeshSize;
  EXPECT_TRUE(IsInSupportedSizeRange(bounds));
  bounds.diagonal = kMaxMeshSize;
  bounds.max_abs = kMaxMeshSize;
  EXPECT_TRUE(IsInSupportedSizeRange(bounds));
  bounds.max_abs = 2 * kMaxMeshSize;  // a small mesh far from the origin
  EXPECT_FALSE(IsInSupportedSizeRange(bounds));
  bounds.max_abs = 1.0;
  bounds.diagonal = 0.5 * kMinMeshSize;
  EXPECT_FALSE(IsInSupportedSizeRange(bounds));
  bounds.diagonal = 2 * kMaxMeshSize;
  EXPECT_FALSE(IsInSupportedSizeRange(bounds));
  bounds.diagonal = HUGE_VAL;
  EXPECT_FALSE(IsInSupportedSizeRange(bounds));
  EXPECT_EQ(SupportedSizeRangeText(),
            "a bounding-box diagonal between 1e-20 m and 1e+20 m and every coordinate within "
            "±1e+20 m");
}

}  // namespace
}  // namespace ecpsim::geometry
