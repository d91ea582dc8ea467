#include "engine/rotation.h"

#include <gtest/gtest.h>

namespace ecpsim::engine {
namespace {

TEST(RotationTest, ExpMapMatchesAngleAxis) {
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.3, -1.2, 0.7), Eigen::Vector3d(1e-8, 0, 2e-8),
                                    Eigen::Vector3d(0, 0, 3.0)}) {
    const Eigen::Matrix3d expected =
        phi.norm() > 0 ? Eigen::AngleAxisd(phi.norm(), phi.normalized()).toRotationMatrix()
                       : Eigen::Matrix3d::Identity();
    EXPECT_LT((ExpMap(phi) - expected).norm(), 1e-15);
    EXPECT_LT((QuaternionExp(phi).toRotationMatrix() - expected).norm(), 1e-15);
  }
}

TEST(RotationTest, LeftJacobianMatchesFiniteDifferences) {
  // ∂/∂φ (Exp(φ) x) = −[Exp(φ) x]× J_l(φ); central differences with step 1e-6 are accurate to
  // ~1e-11 for this smooth map
  const Eigen::Vector3d x(0.4, -0.2, 0.9);
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.3, -1.2, 0.7), Eigen::Vector3d(1e-7, 2e-7, 0)}) {
    const Eigen::Matrix3d analytic = -Skew(ExpMap(phi) * x) * LeftJacobian(phi);
    for (int k = 0; k < 3; ++k) {
      const double eps = 1e-6;
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * eps;
      const Eigen::Vector3d numeric = (ExpMap(phi + d) * x - ExpMap(phi - d) * x) / (2 * eps);
      EXPECT_LT((numeric - analytic.col(k)).norm(), 1e-9) << "column " << k;
    }
  }
}

TEST(RotationTest, IntegrateOrientationStaysUnit) {
  Eigen::Quaterniond Q = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d w(3, -7, 11);
  for (int i = 0; i < 10000; ++i) Q = IntegrateOrientation(Q, w, 0.01);
  EXPECT_NEAR(Q.norm(), 1.0, 1e-14);
  // a constant spin: the composition equals one exponential of the total angle
  const Eigen::Matrix3d expected = ExpMap(w * 100.0);
  EXPECT_LT((Q.toRotationMatrix() - expected).norm(), 1e-9);
}

}  // namespace
}  // namespace ecpsim::engine
