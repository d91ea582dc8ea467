// A convex shape's support features on a plane it touches: a box's face, a cylinder's side and
// end, a sphere's point — whatever way the shape is turned about the plane's normal.

#include "geometry/support_patch.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ecpsim::geometry {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

// m: the patch tolerance the selection passes (1e-6 of a 0.1 m body's size) ...
constexpr double kTolerance = 1e-7;
// ... and the features' coordinates, exact support points of exact shapes, to round-off
constexpr double kRoundOff = 1e-14;

// `shape` turned by `yaw` about z, resting on the ground z = 0 at its lowest point
Isometry3d OnGround(const ConvexShape& shape, double yaw) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = Vector3d(0.3, -0.2, -(X.linear() * shape.Support(-Vector3d::UnitZ())).z());
  return X;
}

TEST(SupportPatchTest, ACylindersSideIsASegmentOfItsLength) {
  const auto cylinder = MakeCylinder(0.01, 0.04, /*axis=*/0);  // lying along x
  for (double yaw : {0.0, 0.4, M_PI / 2}) {
    const ContactPatch patch =
        SupportPatch(*cylinder, OnGround(*cylinder, yaw), Plane{}, kTolerance);
    ASSERT_EQ(patch.segments.size(), 1u) << yaw;
    // to the tolerance: a probe whose support leaves the plane by less than it counts
    EXPECT_NEAR((patch.segments[0][1] - patch.segments[0][0]).norm(), 0.04, kTolerance) << yaw;
    EXPECT_EQ(patch.mode, ContactMode::kLine);
  }
}

TEST(SupportPatchTest, ACylindersEndIsAnInscribedPolygonOfItsDisc) {
  const auto cylinder = MakeCylinder(0.01, 0.04, /*axis=*/2);  // standing on its end
  const ContactPatch patch = SupportPatch(*cylinder, OnGround(*cylinder, 0.3), Plane{}, kTolerance);
  ASSERT_EQ(patch.polygons.size(), 1u);
  // a regular kSupportProbes-gon inscribed in the disc: (n/2) r² sin(2π/n)
  const double n = kSupportProbes;
  EXPECT_NEAR(patch.area, n / 2 * 1e-4 * std::sin(2 * M_PI / n), 1e-6 * patch.area);
}

TEST(SupportPatchTest, ABoxsFaceAndASpheresPoint) {
  const auto box = MakeBox(Vector3d(0.1, 0.05, 0.02));
  const ContactPatch face = SupportPatch(*box, OnGround(*box, 0.7), Plane{}, kTolerance);
  ASSERT_EQ(face.polygons.size(), 1u);
  EXPECT_NEAR(face.area, 0.2 * 0.1, kRoundOff);
  const auto sphere = MakeSphere(0.05);
  const ContactPatch point = SupportPatch(*sphere, OnGround(*sphere, 0.7), Plane{}, kTolerance);
  ASSERT_EQ(point.points.size(), 1u);
  EXPECT_NEAR(point.points[0].x(), 0.3, kRoundOff);
  EXPECT_NEAR(point.points[0].y(), -0.2, kRoundOff);
  EXPECT_EQ(point.mode, ContactMode::kPoint);
}

}  // namespace
}  // namespace ecpsim::geometry
