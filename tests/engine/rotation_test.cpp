#include "engine/rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/tolerances.h"

namespace ecpsim::engine {
namespace {

TEST(RotationTest, ExpMapMatchesAngleAxis) {
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.3, -1.2, 0.7),
                                     Eigen::Vector3d(1e-8, 0, 2e-8), Eigen::Vector3d(0, 0, 3.0)}) {
    const Eigen::Matrix3d expected =
        phi.norm() > 0 ? Eigen::AngleAxisd(phi.norm(), phi.normalized()).toRotationMatrix()
                       : Eigen::Matrix3d::Identity();
    EXPECT_LT((ExpMap(phi) - expected).norm(), kUnitRoundOff);
    EXPECT_LT((QuaternionExp(phi).toRotationMatrix() - expected).norm(), kUnitRoundOff);
  }
}

TEST(RotationTest, LeftJacobianMatchesFiniteDifferences) {
  // ∂/∂φ (Exp(φ) x) = −[Exp(φ) x]× J_l(φ); central differences with step 1e-6 are accurate to
  // ~1e-11 for this smooth map, and 1e-9 keeps a factor 100 over that
  constexpr double kFiniteDifference = 1e-9;
  const Eigen::Vector3d x(0.4, -0.2, 0.9);
  for (const Eigen::Vector3d& phi :
       {Eigen::Vector3d(0.3, -1.2, 0.7), Eigen::Vector3d(1e-7, 2e-7, 0)}) {
    const Eigen::Matrix3d analytic = -Skew(ExpMap(phi) * x) * LeftJacobian(phi);
    for (int k = 0; k < 3; ++k) {
      const double eps = 1e-6;
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * eps;
      const Eigen::Vector3d numeric = (ExpMap(phi + d) * x - ExpMap(phi - d) * x) / (2 * eps);
      EXPECT_LT((numeric - analytic.col(k)).norm(), kFiniteDifference) << "column " << k;
    }
  }
}

TEST(RotationTest, IntegrateOrientationStaysUnit) {
  Eigen::Quaterniond Q = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d w(3, -7, 11);
  for (int i = 0; i < 10000; ++i) Q = IntegrateOrientation(Q, w, 0.01);
  // the norm stays 1 to a few dozen ulps over the 10⁴ normalised products
  constexpr double kNormRoundOff = 1e-14;
  EXPECT_NEAR(Q.norm(), 1.0, kNormRoundOff);
  // a constant spin: the composition equals one exponential of the total angle, up to the
  // round-off of 10⁴ products and of that 1350 rad angle (one ulp is 2.3e-13 rad)
  constexpr double kCompositionRoundOff = 1e-9;
  const Eigen::Matrix3d expected = ExpMap(w * 100.0);
  EXPECT_LT((Q.toRotationMatrix() - expected).norm(), kCompositionRoundOff);
}

TEST(RotationTest, QuaternionLogInvertsQuaternionExp) {
  // a few ulps of the angle, relative for small angles (atan2 and the products keep relative
  // precision as the angle → 0), absolute for O(1) ones
  constexpr double kLogRoundOff = 8 * std::numeric_limits<double>::epsilon();
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 2) / 3;
  for (double angle : {0.0, 1e-150, 1e-12, 1e-7, 0.5, 3.0, M_PI - 1e-6}) {
    const Eigen::Vector3d phi = angle * axis;
    const Eigen::Quaterniond q = QuaternionExp(phi);
    const double tolerance = kLogRoundOff * angle;
    EXPECT_LE((QuaternionLog(q) - phi).norm(), tolerance) << "angle " << angle;
    // −q is the same rotation: the same shortest arc
    EXPECT_LE((QuaternionLog(Eigen::Quaterniond(-q.coeffs())) - phi).norm(), tolerance)
        << "angle " << angle;
    // not normalized: the same angle
    EXPECT_LE((QuaternionLog(Eigen::Quaterniond(3 * q.coeffs())) - phi).norm(), tolerance)
        << "angle " << angle;
  }
  // a turn of 3π/2 is the shortest arc of −π/2
  const Eigen::Quaterniond q(Eigen::AngleAxisd(1.5 * M_PI, Eigen::Vector3d::UnitZ()));
  EXPECT_LE((QuaternionLog(q) - Eigen::Vector3d(0, 0, -M_PI / 2)).norm(), kLogRoundOff * M_PI);
}

TEST(RotationTest, RpyTurnsAboutWorldXThenYThenZ) {
  // unit vectors a few flops from exact right angles: ulps of 1
  constexpr double kAxisRoundOff = 1e-15;
  // roll 90° takes y to z, then yaw 90° takes x to y and leaves z
  const Eigen::Matrix3d R =
      RpyToQuaternion(Eigen::Vector3d(M_PI / 2, 0, M_PI / 2)).toRotationMatrix();
  EXPECT_LT((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), kAxisRoundOff);
  EXPECT_LT((R * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), kAxisRoundOff);
  // pitch 90° takes z to x, then yaw 90° takes x to y
  const Eigen::Matrix3d P =
      RpyToQuaternion(Eigen::Vector3d(0, M_PI / 2, M_PI / 2)).toRotationMatrix();
  EXPECT_LT((P * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitY()).norm(), kAxisRoundOff);
}

}  // namespace
}  // namespace ecpsim::engine
