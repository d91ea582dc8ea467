#include "geometry/convex_separation.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace ecpsim::geometry {
namespace {

// relative to the shapes' size: PenetrationDepth's own accuracy on polyhedra (EPA's stop),
// with a factor 10 for the polytope's last face not being the exact one
constexpr double kDepthRel = 10 * kPenetrationRelTolerance;
// relative to the depth: on a curved shape EPA's polytope is inscribed, so the depth comes out
// low by up to kCurvedDepthRel (convex_separation.h)
constexpr double kCurvedDepthRel = kPenetrationCurvedRelError;
// relative: a separation along an axis is a difference of two support values, exact to
// round-off of the coordinates
constexpr double kRoundOffRel = 1e-12;
// relative to the shapes' size: coordinates 10⁵ sizes from the origin keep ~11 digits of it
constexpr double kFarRoundOffRel = 1e-9;

Eigen::Isometry3d At(const Eigen::Vector3d& p, double yaw = 0) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = p;
  return X;
}

TEST(ConvexSeparationTest, BoxesSideBySideAreSeparatedByTheirGapAlongTheFaceNormal) {
  const auto a = MakeBox(Eigen::Vector3d(0.5, 0.5, 0.5));
  const auto b = MakeBox(Eigen::Vector3d(0.5, 0.5, 0.5));
  // b 0.3 beside a along −x and shifted in y and z, so the centre line is no separating axis
  const Eigen::Vector3d offset(-1.3, 0.8, -0.9);
  const AxisSeparation best = BestSeparatingAxis(*a, At({0, 0, 0}), *b, At(offset));
  EXPECT_NEAR(best.separation, 0.3, kRoundOffRel);
  EXPECT_NEAR(best.axis.x(), 1, kRoundOffRel);  // from b toward a
  // the line of the centres separates them by less
  const AxisSeparation centres =
      SeparationAlong(*a, At({0, 0, 0}), *b, At(offset), -offset.normalized());
  EXPECT_LT(centres.separation, 0.1);
  EXPECT_EQ(PenetrationDepth(*a, At({0, 0, 0}), *b, At(offset), 1), 0);
}

TEST(ConvexSeparationTest, OverlappingBoxesPenetrateByTheirOverlapAtAnyScaleAndPlace) {
  const Eigen::Vector3d half(0.5, 0.5, 0.5);
  // b 0.2 into a along x (0.9 between the centres), turned a little about z; at metre, millimetre
  // and kilometre scale, and 10⁵ sizes away from the origin
  for (const double unit : {1.0, 1e-3, 1e3}) {
    for (const double far : {0.0, 1e5}) {
      const auto a = MakeBox(unit * half);
      const auto b = MakeBox(unit * half);
      const Eigen::Vector3d origin(far * unit, -far * unit, 0);
      const Eigen::Isometry3d X_a = At(origin),
                              X_b = At(origin + unit * Eigen::Vector3d(0.9, 0.1, 0));
      const double depth = PenetrationDepth(*a, X_a, *b, X_b, unit);
      EXPECT_NEAR(depth, 0.1 * unit, kDepthRel * unit) << unit << " " << far;
      const AxisSeparation best = BestSeparatingAxis(*a, X_a, *b, X_b);
      EXPECT_NEAR(best.separation, -0.1 * unit, kFarRoundOffRel * unit) << unit << " " << far;
    }
  }
}

TEST(ConvexSeparationTest, SmoothShapesOverlapByTheirRadiiLessTheirDistance) {
  // two spheres 1 apart with radii 0.6: 0.2 deep; 0.1 apart with radii 0.45: none
  const auto big = MakeSphere(0.6), small = MakeSphere(0.45);
  const double spheres = PenetrationDepth(*big, At({0, 0, 0}), *big, At({0.6, 0.8, 0}), 1);
  EXPECT_LE(spheres, 0.2 + kDepthRel);
  EXPECT_GE(spheres, 0.2 * (1 - kCurvedDepthRel));
  EXPECT_EQ(PenetrationDepth(*small, At({0, 0, 0}), *small, At({0.6, 0, 0.8}), 1), 0);
  // an upright rod beside a long box's vertical edge, 0.01 from it on the diagonal: neither the
  // line of the centres (nearly along the box) nor a face normal or world axis separates them,
  // GJK does
  const auto box = MakeBox(Eigen::Vector3d(0.5, 3, 0.5));
  const auto rod = MakeCylinder(0.2, 2, 2);  // along z
  const auto beside = [](double axis_to_edge) {
    const double d = axis_to_edge / std::sqrt(2.0);
    return At({0.5 + d, 3 + d, 0});
  };
  EXPECT_LT(BestSeparatingAxis(*box, At({0, 0, 0}), *rod, beside(0.21)).separation, 0);
  EXPECT_EQ(PenetrationDepth(*box, At({0, 0, 0}), *rod, beside(0.21), 1), 0);
  // 0.11 from it the rod overlaps the edge by 0.09, the shortest way out along the diagonal
  const double edge = PenetrationDepth(*box, At({0, 0, 0}), *rod, beside(0.11), 1);
  EXPECT_LE(edge, 0.09 + kDepthRel);
  EXPECT_GE(edge, 0.09 * (1 - kCurvedDepthRel));
}

TEST(ConvexSeparationTest, WithinDistanceIsTheGapBetweenTheShapesInAnyFrameAndAtAnyScale) {
  // two boxes side by side 0.3 apart along the faces' normal, offset across it by less than a
  // face, and turned together about z by 37°; a sphere 0.25 beyond a box's corner along its
  // diagonal. At metre, millimetre and kilometre scale, 10⁵ sizes away from the origin
  const double turn = 37 * M_PI / 180;
  for (const double unit : {1.0, 1e-3, 1e3}) {
    for (const double far : {0.0, 1e5}) {
      const auto a = MakeBox(unit * Eigen::Vector3d(0.5, 0.5, 0.5));
      const auto b = MakeBox(unit * Eigen::Vector3d(0.5, 0.5, 0.5));
      const Eigen::Vector3d origin(far * unit, -far * unit, 0);
      for (const double yaw : {0.0, turn}) {
        const Eigen::Vector3d offset =
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(1.3, 0.4, 0.2);
        const Eigen::Isometry3d X_a = At(origin, yaw), X_b = At(origin + unit * offset, yaw);
        EXPECT_FALSE(WithinDistance(*a, X_a, *b, X_b, 0.29 * unit, unit)) << unit << " " << yaw;
        EXPECT_TRUE(WithinDistance(*a, X_a, *b, X_b, 0.31 * unit, unit)) << unit << " " << yaw;
        // either way round
        EXPECT_FALSE(WithinDistance(*b, X_b, *a, X_a, 0.29 * unit, unit)) << unit << " " << yaw;
        EXPECT_TRUE(WithinDistance(*b, X_b, *a, X_a, 0.31 * unit, unit)) << unit << " " << yaw;
      }
      const auto sphere = MakeSphere(0.5 * unit);
      const Eigen::Isometry3d corner =
          At(origin + unit * (0.5 + 0.75 / std::sqrt(3.0)) * Eigen::Vector3d::Ones());
      EXPECT_FALSE(WithinDistance(*a, At(origin), *sphere, corner, 0.24 * unit, unit)) << unit;
      EXPECT_TRUE(WithinDistance(*a, At(origin), *sphere, corner, 0.26 * unit, unit)) << unit;
    }
  }
  // overlapping shapes are within any distance, and an infinite one reaches everything
  const auto box = MakeBox(Eigen::Vector3d(0.5, 0.5, 0.5));
  EXPECT_TRUE(WithinDistance(*box, At({0, 0, 0}), *box, At({0.9, 0, 0}), 0, 1));
  EXPECT_TRUE(WithinDistance(*box, At({0, 0, 0}), *box, At({1e3, 0, 0}), INFINITY, 1));
}

}  // namespace
}  // namespace ecpsim::geometry
