// UncoveredFaces and LidSlabs: the faces of a hull its convex parts do not cover, and the slabs
// under them.

#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/convex_shape.h"
#include "geometry/hull_lids.h"
#include "geometry/posed_shape.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector3d;

constexpr double kTolerance = 1e-9;           // m: the shapes are 1 m boxes given exactly
constexpr double kSize = 1.7320508075688772;  // m: the unit cube's diagonal

// a box of `size` centred at `centre`
std::shared_ptr<const ConvexShape> Box(const Vector3d& size, const Vector3d& centre) {
  return Posed(MakeBox(0.5 * size), Eigen::Matrix3d::Identity(), centre);
}

std::vector<int> Uncovered(const std::vector<std::shared_ptr<const ConvexShape>>& parts) {
  std::vector<const ConvexHull*> hulls;
  for (const auto& part : parts) hulls.push_back(&part->AsPolyhedron()->hull());
  return UncoveredFaces(MakeBox(Vector3d::Constant(0.5))->hull(), hulls, kTolerance, kSize);
}

// the unit outward normals of `faces` of the unit cube's hull
std::vector<Vector3d> Normals(const std::vector<int>& faces) {
  const ConvexHull cube = MakeBox(Vector3d::Constant(0.5))->hull();
  std::vector<Vector3d> normals;
  for (int f : faces) normals.push_back(cube.normals[f]);
  return normals;
}

TEST(HullLidsTest, AChannelOpenAtTheTopAndTheEndsHasThreeLids) {
  // a floor 0.2 m thick and two walls 0.2 m thick reaching into it, along y
  const std::vector<int> lids =
      Uncovered({Box({1, 1, 0.2}, {0, 0, -0.4}), Box({0.2, 1, 1}, {-0.4, 0, 0}),
                 Box({0.2, 1, 1}, {0.4, 0, 0})});
  ASSERT_EQ(lids.size(), 3u);
  int top = 0, ends = 0;
  for (const Vector3d& n : Normals(lids)) {
    top += n.isApprox(Vector3d::UnitZ(), 1e-15);
    ends += std::abs(std::abs(n.y()) - 1) < 1e-15;
  }
  EXPECT_EQ(top, 1);
  EXPECT_EQ(ends, 2);
}

TEST(HullLidsTest, OverlappingPartsCoverAFaceTogetherAndAGapBetweenThemIsALid) {
  // two halves reaching 0.1 m into each other: the cube, no lid
  EXPECT_TRUE(Uncovered({Box({0.6, 1, 1}, {-0.2, 0, 0}), Box({0.6, 1, 1}, {0.2, 0, 0})}).empty());
  // two 0.45 m slabs with a 0.1 m gap between them: each face across the gap is a lid
  const std::vector<int> lids =
      Uncovered({Box({0.45, 1, 1}, {-0.275, 0, 0}), Box({0.45, 1, 1}, {0.275, 0, 0})});
  EXPECT_EQ(lids.size(), 4u);
  for (const Vector3d& n : Normals(lids)) EXPECT_NEAR(n.x(), 0, 1e-15);
}

TEST(HullLidsTest, ASlabLiesUnderItsFace) {
  const ConvexHull cube = MakeBox(Vector3d::Constant(0.5))->hull();
  int top = 0;
  while (!cube.normals[top].isApprox(Vector3d::UnitZ(), 1e-15)) ++top;
  const ConvexHull slab = LidSlab(cube, top, 0.01);
  ASSERT_EQ(slab.vertices.size(), 8u);
  for (const Vector3d& v : slab.vertices) {
    EXPECT_NEAR(std::abs(v.x()), 0.5, 1e-15);
    EXPECT_TRUE(std::abs(v.z() - 0.5) < 1e-15 || std::abs(v.z() - 0.49) < 1e-15) << v.z();
  }
}

TEST(HullLidsTest, LidSlabsOfASmoothHullAreTheHull) {
  const std::shared_ptr<const ConvexShape> cylinder = MakeCylinder(0.5, 1);
  const auto lids = LidSlabs(cylinder, {Box({0.2, 0.2, 1}, Vector3d::Zero())});
  ASSERT_EQ(lids.size(), 1u);
  EXPECT_EQ(lids.front(), cylinder);
}

TEST(HullLidsTest, LidSlabsOfACupAreItsOpening) {
  // the unit cube as a cup: a floor and four walls; one slab, 1e-3 of the diagonal deep
  const auto lids = LidSlabs(MakeBox(Vector3d::Constant(0.5)),
                             {Box({1, 1, 0.2}, {0, 0, -0.4}), Box({0.2, 1, 1}, {-0.4, 0, 0}),
                              Box({0.2, 1, 1}, {0.4, 0, 0}), Box({1, 0.2, 1}, {0, -0.4, 0}),
                              Box({1, 0.2, 1}, {0, 0.4, 0})});
  ASSERT_EQ(lids.size(), 1u);
  const Vector3d top = lids.front()->Support(Vector3d::UnitZ());
  const Vector3d bottom = lids.front()->Support(-Vector3d::UnitZ());
  EXPECT_NEAR(top.z(), 0.5, 1e-15);
  EXPECT_NEAR(bottom.z(), 0.5 - kLidDepthRel * kSize, 1e-15);
}

}  // namespace
}  // namespace ecpsim::geometry
