// A patch's load centre and mean distance from a point against closed forms, and its area
// moments: squares, rectangles, a hole, several polygons, either orientation, no area.

#include "geometry/patch_moments.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

const Plane kGround;  // z = 0, normal +z

// relative: a few dozen ulps of a sum of a few dozen closed-form terms (asinh, hypot) per edge
constexpr double kRelRoundOff = 1e-13;

// the square's mean distance from its centre over its side: (√2 + asinh 1) / 6 = 0.38260
const double kSquareMeanOverSide = (std::sqrt(2.0) + std::asinh(1.0)) / 6;

// ∫∫ sqrt(x² + y²) over [0, w] × [0, h] (m³), the rectangle about its corner, in Cartesian form
// (integrated over y, then x): an independent derivation from the code's polar one per edge
double CornerIntegral(double w, double h) {
  const double d = std::hypot(w, h);
  return (2 * w * h * d + w * w * w * std::log((h + d) / w) + h * h * h * std::log((w + d) / h)) /
         6;
}

// ∫|x − c| dA / A over the axis-aligned rectangle [x0, x1] × [y0, y1] with c inside it: the four
// rectangles with a corner at c
double RectangleMeanDistance(double x0, double x1, double y0, double y1, const Vector2d& c) {
  double integral = 0;
  for (double w : {c.x() - x0, x1 - c.x()})
    for (double h : {c.y() - y0, y1 - c.y()})
      if (w > 0 && h > 0) integral += CornerIntegral(w, h);
  return integral / ((x1 - x0) * (y1 - y0));
}

ContactPatch PolygonPatch(std::vector<Vector3d> polygon) {
  ContactPatch patch;
  patch.polygons.push_back(std::move(polygon));
  return patch;
}

std::vector<Vector3d> Square(double side, const Vector3d& centre) {
  const double s = side / 2;
  return {centre + Vector3d(-s, -s, 0), centre + Vector3d(s, -s, 0), centre + Vector3d(s, s, 0),
          centre + Vector3d(-s, s, 0)};
}

TEST(PatchMeanDistanceTest, ASquareAboutItsCentreIsItsSideTimes0_3826) {
  for (double side : {1e-3, 0.2, 40.0}) {
    const Vector3d centre(0.3, -1.2, 0);
    const ContactPatch patch = PolygonPatch(Square(side, centre));
    EXPECT_NEAR(PatchMeanDistance(patch, kGround, centre), kSquareMeanOverSide * side,
                kRelRoundOff * side);
    // the centroid, and the same for the square traced clockwise
    EXPECT_LE((PatchCentroid(patch, kGround) - centre).norm(), kRelRoundOff * (1 + side));
    std::vector<Vector3d> reversed = Square(side, centre);
    std::reverse(reversed.begin(), reversed.end());
    EXPECT_NEAR(PatchMeanDistance(PolygonPatch(reversed), kGround, centre),
                kSquareMeanOverSide * side, kRelRoundOff * side);
  }
  EXPECT_NEAR(kSquareMeanOverSide, 0.3826, 5e-5);  // the four digits
}

TEST(PatchMeanDistanceTest, ASquareAboutACornerAndAboutAnOffCentrePointMatchTheCartesianForm) {
  const double side = 0.2;
  const ContactPatch patch = PolygonPatch(Square(side, Vector3d::Zero()));
  // about a corner: the quadrant of a square twice as large, 2 × 0.3826 a
  const Vector3d corner(-0.1, -0.1, 0);
  EXPECT_NEAR(PatchMeanDistance(patch, kGround, corner), 2 * kSquareMeanOverSide * side,
              kRelRoundOff * side);
  // an ECP shifted off the centre (a push's tipping moment moves it), 2 cm and 3 cm
  for (const Vector2d& c : {Vector2d(0.03, -0.02), Vector2d(-0.0999, 0.05), Vector2d(0, 0)}) {
    const double expected = RectangleMeanDistance(-0.1, 0.1, -0.1, 0.1, c);
    EXPECT_NEAR(PatchMeanDistance(patch, kGround, Vector3d(c.x(), c.y(), 0)), expected,
                kRelRoundOff * side)
        << c.transpose();
  }
  // the height of the centre above the plane does not count: distances are in the plane
  EXPECT_NEAR(PatchMeanDistance(patch, kGround, Vector3d(0, 0, 0.7)), kSquareMeanOverSide * side,
              kRelRoundOff * side);
}

TEST(PatchMeanDistanceTest, ANonConvexTAboutAPointInItsBarMatchesItsTwoRectangles) {
  // the T: a bar [−0.15, 0.15] × [0.05, 0.1] on a stem [−0.025, 0.025] × [−0.1, 0.05], ccw
  const std::vector<Vector3d> t = {{-0.025, -0.1, 0}, {0.025, -0.1, 0}, {0.025, 0.05, 0},
                                   {0.15, 0.05, 0},   {0.15, 0.1, 0},   {-0.15, 0.1, 0},
                                   {-0.15, 0.05, 0},  {-0.025, 0.05, 0}};
  const Vector2d c(0.01, 0.06);
  // ∫ over the bar about c plus ∫ over the stem about c (c outside the stem: the stem's
  // rectangle is the difference of two corner rectangles below c's row)
  const auto corner_sum = [&](double x0, double x1, double y0, double y1) {
    return RectangleMeanDistance(x0, x1, y0, y1, c) * (x1 - x0) * (y1 - y0);
  };
  const double bar = corner_sum(-0.15, 0.15, 0.05, 0.1);
  // the stem [−0.025, 0.025] × [−0.1, 0.05] lies below c (c.y = 0.06): the column
  // [−0.025, 0.025] × [−0.1, 0.06] minus its top strip [−0.025, 0.025] × [0.05, 0.06]
  const auto column = [&](double y0) {
    double integral = 0;
    for (double w : {c.x() + 0.025, 0.025 - c.x()}) integral += CornerIntegral(w, c.y() - y0);
    return integral;
  };
  const double stem = column(-0.1) - column(0.05);
  const double area = 0.3 * 0.05 + 0.05 * 0.15;
  EXPECT_NEAR(PatchMeanDistance(PolygonPatch(t), kGround, Vector3d(c.x(), c.y(), 0)),
              (bar + stem) / area, kRelRoundOff * 0.3);
}

TEST(PatchMeanDistanceTest, ARegularPolygonLiesBetweenItsInscribedAndCircumscribedDiscs) {
  // a regular n-gon holds the disc of its apothem a and lies in that of its radius R: its mean
  // distance from the centre is between 2a/3 and 2R/3 (n ≥ 4: what the bigger disc adds lies
  // farther than a > 2R/3), a band of 2R(1 − cos(π/n))/3 about the disc's 2R/3
  const double radius = 0.05;
  for (int n : {16, 64, 1024}) {
    std::vector<Vector3d> polygon;
    for (int k = 0; k < n; ++k) {
      const double angle = 2 * M_PI * k / n;
      polygon.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0);
    }
    const double apothem = radius * std::cos(M_PI / n);
    const double mean = PatchMeanDistance(PolygonPatch(polygon), kGround, Vector3d::Zero());
    EXPECT_GE(mean, 2 * apothem / 3 * (1 - kRelRoundOff)) << n;
    EXPECT_LE(mean, 2 * radius / 3 * (1 + kRelRoundOff)) << n;
  }
}

TEST(PatchMeanDistanceTest, ASegmentAboutItsMiddleIsAQuarterOfItsLengthAboutAnEndAHalf) {
  const double length = 0.3;
  ContactPatch patch;
  patch.segments.push_back({Vector3d(-0.15, 0.02, 0), Vector3d(0.15, 0.02, 0)});
  EXPECT_EQ(LoadedFeatures(patch), PatchLoad::kLine);
  EXPECT_NEAR(PatchMeanDistance(patch, kGround, Vector3d(0, 0.02, 0)), length / 4,
              kRelRoundOff * length);
  EXPECT_NEAR(PatchMeanDistance(patch, kGround, Vector3d(0.15, 0.02, 0)), length / 2,
              kRelRoundOff * length);
  // off its line by d about its middle: ∫ sqrt(d² + s²) ds / L, with d = 0.02 m (closed form
  // [s r + d² asinh(s/d)] / 2 at s = ±L/2)
  const double d = 0.02, s = length / 2;
  const double expected = (s * std::hypot(d, s) + d * d * std::asinh(s / d)) / length;
  EXPECT_NEAR(PatchMeanDistance(patch, kGround, Vector3d::Zero()), expected, kRelRoundOff * length);
  EXPECT_LE((PatchCentroid(patch, kGround) - Vector3d(0, 0.02, 0)).norm(), kRelRoundOff * length);
}

TEST(PatchMeanDistanceTest, APointIsZeroAndPointsShareTheLoadEqually) {
  ContactPatch point;
  point.points.push_back(Vector3d(0.1, 0.2, 0));
  EXPECT_EQ(PatchMeanDistance(point, kGround, Vector3d(0.1, 0.2, 0)), 0);
  ContactPatch two;
  two.points = {Vector3d(-0.1, 0, 0), Vector3d(0.1, 0, 0)};
  EXPECT_NEAR(PatchMeanDistance(two, kGround, PatchCentroid(two, kGround)), 0.1,
              kRelRoundOff * 0.1);
  EXPECT_EQ(PatchMeanDistance(ContactPatch{}, kGround, Vector3d::Zero()), 0);
}

TEST(PatchMeanDistanceTest, AreaCarriesTheLoadWhenAPatchAlsoHasSegmentsAndPoints) {
  ContactPatch patch = PolygonPatch(Square(0.2, Vector3d::Zero()));
  patch.segments.push_back({Vector3d(1, 0, 0), Vector3d(2, 0, 0)});
  patch.points.push_back(Vector3d(5, 5, 0));
  EXPECT_EQ(LoadedFeatures(patch), PatchLoad::kArea);
  EXPECT_NEAR(PatchMeanDistance(patch, kGround, Vector3d::Zero()), kSquareMeanOverSide * 0.2,
              kRelRoundOff * 0.2);
}

TEST(PatchMeanDistanceTest, ABoxLyingOnATiltedPlaneGivesItsFaceAsExtracted) {
  // a 0.2 × 0.1 m face of a box extracted on a plane tilted 30° about x: the rectangle's
  // closed form about its centroid, whatever the plane's basis
  const double angle = M_PI / 6;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Vector3d::UnitX()).toRotationMatrix();
  const Plane plane{R * Vector3d::UnitZ(), 0.4};
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = R;
  X_WB.translation() = plane.normal * (0.4 + 0.025);
  const TriangleMesh box =
      testing::MakeBoxMesh(Vector3d(-0.1, -0.05, -0.025), Vector3d(0.1, 0.05, 0.025));
  const ContactPatch patch = ExtractContactPatch(box, X_WB, plane);
  ASSERT_EQ(patch.mode, ContactMode::kConvexPatch);
  const Vector3d centroid = PatchCentroid(patch, plane);
  EXPECT_LE((centroid - plane.offset * plane.normal).norm(), kRelRoundOff);
  EXPECT_NEAR(PatchMeanDistance(patch, plane, centroid),
              RectangleMeanDistance(-0.1, 0.1, -0.05, 0.05, Vector2d::Zero()), kRelRoundOff * 0.2);
}

// moments of exact polygons: sums of a few products of O(1) coordinates, to round-off
constexpr double kMomentRoundOff = 1e-15;

std::vector<Vector3d> Rectangle(const Vector3d& centre, double a, double b) {
  return {centre + Vector3d(-a / 2, -b / 2, 0), centre + Vector3d(a / 2, -b / 2, 0),
          centre + Vector3d(a / 2, b / 2, 0), centre + Vector3d(-a / 2, b / 2, 0)};
}

TEST(PatchMomentsTest, ARectanglesAreaCentroidAndPrincipalMoments) {
  ContactPatch patch;
  patch.polygons.push_back(Rectangle({0.3, -0.2, 0}, 0.4, 0.1));
  const PatchMoments m = MomentsOf(patch, Plane{}, 0);
  EXPECT_NEAR(m.area, 0.04, kMomentRoundOff);
  EXPECT_LT((m.centroid - Vector3d(0.3, -0.2, 0)).norm(), kMomentRoundOff);
  // along the long side: b a³ / 12; across it: a b³ / 12
  EXPECT_NEAR(m.I1, 0.1 * std::pow(0.4, 3) / 12, kMomentRoundOff);
  EXPECT_NEAR(m.I2, 0.4 * std::pow(0.1, 3) / 12, kMomentRoundOff);
  EXPECT_NEAR(std::abs(m.u1.x()), 1, kMomentRoundOff);
  EXPECT_NEAR(std::abs(m.u2.y()), 1, kMomentRoundOff);
}

TEST(PatchMomentsTest, APatchCountsTheSameWhicheverWayItsLoopsTurn) {
  ContactPatch ccw, cw;
  ccw.polygons.push_back(Rectangle({0, 0, 0}, 0.2, 0.2));
  cw.polygons.push_back({ccw.polygons[0].rbegin(), ccw.polygons[0].rend()});
  const PatchMoments a = MomentsOf(ccw, Plane{}, 0), b = MomentsOf(cw, Plane{}, 0);
  EXPECT_NEAR(a.area, b.area, kMomentRoundOff);
  EXPECT_NEAR(a.I1, b.I1, kMomentRoundOff);
  EXPECT_NEAR(a.I1, std::pow(0.2, 4) / 12, kMomentRoundOff);
}

TEST(PatchMomentsTest, AHoleTracedAgainstItsOuterLoopIsTakenAway) {
  // a 0.4 m square with a 0.2 m square hole: A = a² − b², I = (a⁴ − b⁴)/12 along either axis
  ContactPatch patch;
  patch.polygons.push_back(Rectangle({0, 0, 0}, 0.4, 0.4));
  const std::vector<Vector3d> inner = Rectangle({0, 0, 0}, 0.2, 0.2);
  patch.polygons.push_back({inner.rbegin(), inner.rend()});
  const PatchMoments m = MomentsOf(patch, Plane{}, 0);
  EXPECT_NEAR(m.area, 0.16 - 0.04, kMomentRoundOff);
  EXPECT_NEAR(m.I1, (std::pow(0.4, 4) - std::pow(0.2, 4)) / 12, kMomentRoundOff);
  EXPECT_NEAR(m.I2, m.I1, kMomentRoundOff);
}

TEST(PatchMomentsTest, FourFeetAddTheirSteinerTerms) {
  // four 0.06 m square feet at the corners of a 0.44 m square (the desk's): A = 4 a², and about
  // the centre I = 4 (a⁴/12 + a² d²) along either axis
  const double a = 0.06, d = 0.22;
  ContactPatch patch;
  for (double x : {-d, d})
    for (double y : {-d, d}) patch.polygons.push_back(Rectangle({x, y, 0}, a, a));
  const PatchMoments m = MomentsOf(patch, Plane{}, 0);
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
  const PatchMoments m = MomentsOf(patch, plane, 0);
  EXPECT_NEAR(m.area, 0.04, kMomentRoundOff);
  EXPECT_LT((m.centroid - Vector3d(0.5, 0, 0)).norm(), kMomentRoundOff);
  EXPECT_NEAR(m.I1, 0.1 * std::pow(0.4, 3) / 12, kMomentRoundOff);
  EXPECT_NEAR(std::abs(m.u1.y()), 1, kMomentRoundOff);
}

TEST(PatchMomentsTest, ALineIsAStripOfTheGivenWidth) {
  // a 1 m segment (and a point beside it, which carries nothing): A = w L, I1 = w L³ / 12 along
  // it, I2 = 0 across
  const double w = 1e-3;
  ContactPatch patch;
  patch.segments.push_back({Vector3d(0, 0, 0), Vector3d(1, 0, 0)});
  patch.points.push_back(Vector3d(0, 1, 0));
  const PatchMoments m = MomentsOf(patch, Plane{}, w);
  EXPECT_NEAR(m.area, w, kMomentRoundOff);
  EXPECT_LT((m.centroid - Vector3d(0.5, 0, 0)).norm(), kMomentRoundOff);
  EXPECT_NEAR(m.I1, w / 12, kMomentRoundOff);
  EXPECT_NEAR(m.I2, 0, kMomentRoundOff);
}

TEST(PatchMomentsTest, PointsAreSquaresOfTheGivenWidth) {
  // two points 1 m apart: A = 2 w², I1 = 2 w² (1/2)² + 2 w⁴/12 along their line, 2 w⁴/12 across
  const double w = 1e-3;
  ContactPatch patch;
  patch.points = {Vector3d(0, 0, 0), Vector3d(0, 1, 0)};
  const PatchMoments m = MomentsOf(patch, Plane{}, w);
  EXPECT_NEAR(m.area, 2 * w * w, kMomentRoundOff);
  EXPECT_LT((m.centroid - Vector3d(0, 0.5, 0)).norm(), kMomentRoundOff);
  EXPECT_NEAR(m.I1, 2 * w * w * 0.25 + 2 * std::pow(w, 4) / 12, kMomentRoundOff);
  EXPECT_NEAR(m.I2, 2 * std::pow(w, 4) / 12, kMomentRoundOff);
  EXPECT_EQ(MomentsOf(ContactPatch{}, Plane{}, w).area, 0);
}

}  // namespace
}  // namespace ecpsim::geometry
