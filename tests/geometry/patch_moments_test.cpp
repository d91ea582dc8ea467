// A patch's area moments against their closed forms: squares, rectangles, a patch of several
// polygons, polygons of either orientation and a patch without area.

#include "geometry/patch_moments.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ecpsim::geometry {
namespace {

using Eigen::Vector3d;

// moments of exact polygons: sums of a few products of O(1) coordinates, to round-off
constexpr double kMomentRoundOff = 1e-15;

std::vector<Vector3d> Rectangle(const Vector3d& centre, double a, double b) {
  return {centre + Vector3d(-a / 2, -b / 2, 0), centre + Vector3d(a / 2, -b / 2, 0),
          centre + Vector3d(a / 2, b / 2, 0), centre + Vector3d(-a / 2, b / 2, 0)};
}

TEST(PatchMomentsTest, ARectanglesAreaCentroidAndPrincipalMoments) {
  ContactPatch patch;
  patch.polygons.push_back(Rectangle({0.3, -0.2, 0}, 0.4, 0.1));
  const PatchMoments m = MomentsOf(patch, Plane{});
  EXPECT_NEAR(m.area, 0.04, kMomentRoundOff);
  EXPECT_LT((m.centroid - Vector3d(0.3, -0.2, 0)).norm(), kMomentRoundOff);
  // along the long side: b a³ / 12; across it: a b³ / 12
  EXPECT_NEAR(m.I1, 0.1 * std::pow(0.4, 3) / 12, kMomentRoundOff);
  EXPECT_NEAR(m.I2, 0.4 * std::pow(0.1, 3) / 12, kMomentRoundOff);
  EXPECT_NEAR(std::abs(m.u1.x()), 1, kMomentRoundOff);
  EXPECT_NEAR(std::abs(m.u2.y()), 1, kMomentRoundOff);
}

TEST(PatchMomentsTest, APolygonCountsTheSameWhicheverWayItTurns) {
  ContactPatch ccw, cw;
  ccw.polygons.push_back(Rectangle({0, 0, 0}, 0.2, 0.2));
  cw.polygons.push_back({ccw.polygons[0].rbegin(), ccw.polygons[0].rend()});
  const PatchMoments a = MomentsOf(ccw, Plane{}), b = MomentsOf(cw, Plane{});
  EXPECT_NEAR(a.area, b.area, kMomentRoundOff);
  EXPECT_NEAR(a.I1, b.I1, kMomentRoundOff);
  EXPECT_NEAR(a.I1, std::pow(0.2, 4) / 12, kMomentRoundOff);
}

TEST(PatchMomentsTest, FourFeetAddTheirSteinerTerms) {
  // four 0.06 m square feet at the corners of a 0.44 m square (the desk's): A = 4 a², and about
  // the centre I = 4 (a⁴/12 + a² d²) along either axis
  const double a = 0.06, d = 0.22;
  ContactPatch patch;
  for (double x : {-d, d})
    for (double y : {-d, d}) patch.polygons.push_back(Rectangle({x, y, 0}, a, a));
  const PatchMoments m = MomentsOf(patch, Plane{});
  EXPECT_NEAR(m.area, 4 * a * a, kMomentRoundOff);
  EXPECT_LT(m.centroid.norm(), kMomentRoundOff);
  EXPECT_NEAR(m.I1, 4 * (std::pow(a, 4) / 12 + a * a * d * d), kMomentRoundOff);
  EXPECT_NEAR(m.I2, m.I1, kMomentRoundOff);
}

TEST(PatchMomentsTest, APatchOnATiltedPlaneIsMeasuredInThatPlane) {
  // the rectangle turned into the plane x = 0.5 (normal +x)
  const Plane plane{Vector3d::UnitX(), 0.5};
  std::vector<Vector3d> turned;
  for (const Vector3d& p : Rectangle({0, 0, 0}, 0.4, 0.1)) turned.emplace_back(0.5, p.x(), p.y());
  ContactPatch patch;
  patch.polygons.push_back(turned);
  const PatchMoments m = MomentsOf(patch, plane);
  EXPECT_NEAR(m.area, 0.04, kMomentRoundOff);
  EXPECT_LT((m.centroid - Vector3d(0.5, 0, 0)).norm(), kMomentRoundOff);
  EXPECT_NEAR(m.I1, 0.1 * std::pow(0.4, 3) / 12, kMomentRoundOff);
  EXPECT_NEAR(std::abs(m.u1.y()), 1, kMomentRoundOff);
}

TEST(PatchMomentsTest, SegmentsAndPointsHaveNoArea) {
  ContactPatch patch;
  patch.segments.push_back({Vector3d(0, 0, 0), Vector3d(1, 0, 0)});
  patch.points.push_back(Vector3d(0, 1, 0));
  EXPECT_EQ(MomentsOf(patch, Plane{}).area, 0);
}

}  // namespace
}  // namespace ecpsim::geometry
