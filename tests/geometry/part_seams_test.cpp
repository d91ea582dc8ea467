// FindSeam: two convex parts that meet face to face over an area, and those that do not.

#include <gtest/gtest.h>

#include "geometry/convex_shape.h"
#include "geometry/part_seams.h"

namespace ecpsim::geometry {
namespace {

constexpr double kTolerance = 1e-9;  // m: the parts are 0.1 m boxes given exactly

// a 0.1 m cube's hull moved by `offset`
ConvexHull CubeAt(const Eigen::Vector3d& offset) {
  ConvexHull hull = MakeBox(Eigen::Vector3d::Constant(0.05))->hull();
  for (Eigen::Vector3d& v : hull.vertices) v += offset;
  for (size_t i = 0; i < hull.normals.size(); ++i) hull.offsets[i] += hull.normals[i].dot(offset);
  return hull;
}

TEST(PartSeamsTest, CubesFaceToFaceMeetAtASeam) {
  const ConvexHull a = CubeAt(Eigen::Vector3d::Zero());
  const std::optional<Seam> seam = FindSeam(a, CubeAt(Eigen::Vector3d(0.1, 0.03, 0)), kTolerance);
  ASSERT_TRUE(seam.has_value());
  EXPECT_NEAR(a.normals[seam->face_a].x(), 1, 1e-15);
  EXPECT_NEAR(seam->centre.x(), 0.05, 1e-15);
}

TEST(PartSeamsTest, CubesThatShareAnEdgeOrCornerOrReachIntoEachOtherDoNot) {
  const ConvexHull a = CubeAt(Eigen::Vector3d::Zero());
  EXPECT_FALSE(FindSeam(a, CubeAt(Eigen::Vector3d(0.1, 0.1, 0)), kTolerance));    // an edge
  EXPECT_FALSE(FindSeam(a, CubeAt(Eigen::Vector3d(0.1, 0.1, 0.1)), kTolerance));  // a corner
  EXPECT_FALSE(FindSeam(a, CubeAt(Eigen::Vector3d(0.09, 0, 0)), kTolerance));     // overlap
  EXPECT_FALSE(FindSeam(a, CubeAt(Eigen::Vector3d(0.11, 0, 0)), kTolerance));     // apart
}

}  // namespace
}  // namespace ecpsim::geometry
