#include "engine/mncp/mncp_system.h"

#include <random>

#include <gtest/gtest.h>

#include "engine/rotation.h"
#include "geometry/convex_shape.h"
#include "tests/engine/jacobian_check.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using testing::kJacobianTolerance;

// a body problem around a given pose; the Jacobian identity holds for any z, so the unknowns are
// filled with plausible random values (positive multipliers, impulses of the size m g h)
struct Fixture {
  BodyProblem problem;
  MncpLayout layout;
  VectorXd z;
};

Fixture MakeFixture(std::shared_ptr<const geometry::ConvexShape> hull,
                    std::shared_ptr<const geometry::ConvexShape> obstacle,
                    const Eigen::Quaterniond& Q, const Vector3d& c, unsigned seed,
                    bool free_flight = false) {
  static std::vector<std::shared_ptr<const geometry::ConvexShape>> keep_alive;
  keep_alive.push_back(hull);
  keep_alive.push_back(obstacle);
  Fixture f;
  BodyProblem& p = f.problem;
  p.h = 0.01;
  p.mass = 2.5;
  p.R = Q.toRotationMatrix();
  p.inertia_world = p.R * Vector3d(0.03, 0.05, 0.07).asDiagonal() * p.R.transpose();
  p.c = c;
  p.v = Vector3d(0.3, -0.2, 0.1);
  p.w = Vector3d(0.5, 1.5, -2.0);
  p.p_ext << 0.01, 0.02, -0.245, 0.001, -0.002, 0.003;
  ContactProblem cp;
  cp.hull = hull.get();
  cp.obstacle = obstacle.get();
  for (int i = 0; i < hull->NumConstraints(); ++i) cp.window.push_back(i);
  cp.friction = Friction{0.3, 1.0, 0.8, 0.1};
  cp.tangent_reference = Vector3d::UnitX();
  p.contacts.push_back(cp);
  f.layout = MakeLayout(p);

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  f.z = VectorXd::Zero(f.layout.size);
  for (int i = 0; i < 6; ++i) f.z[i] = (i < 3 ? p.v[i] : p.w[i - 3]) + 0.3 * u(rng);
  const MncpLayout::Contact& L = f.layout.contacts[0];
  for (int i = 0; i < 3; ++i) {
    f.z[L.a1 + i] = c[i] + 0.1 * u(rng);
    f.z[L.a2 + i] = c[i] + 0.1 * u(rng);
  }
  f.z[L.s] = 0.01 * u(rng);
  const double impulse = free_flight ? 0.0 : 0.25;
  f.z[L.p_t] = impulse * 0.2 * u(rng);
  f.z[L.p_o] = impulse * 0.2 * u(rng);
  f.z[L.p_r] = impulse * 0.02 * u(rng);
  f.z[L.p_n] = impulse * (1 + 0.5 * u(rng));
  f.z[L.sigma] = 0.2 + 0.1 * u(rng);
  for (int i = 0; i < L.l_count; ++i) f.z[L.l + i] = 0.5 + 0.5 * u(rng);
  for (int j = 0; j < L.l_g_count; ++j) f.z[L.l_g + j] = (1.0 + 0.3 * u(rng)) / L.l_g_count;
  return f;
}

double JacobianError(const Fixture& f) {
  return testing::JacobianError(
      [&f](const VectorXd& z, VectorXd* F, Eigen::MatrixXd* J) {
        EvaluateMncp(f.problem, f.layout, z, F, J);
      },
      f.z);
}

const auto kGround = geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);

TEST(MncpJacobianTest, FaceContactOnGround) {
  const auto box = geometry::MakeBox(Vector3d(0.25, 0.25, 0.05));
  EXPECT_LT(JacobianError(
                MakeFixture(box, kGround, Eigen::Quaterniond::Identity(), Vector3d(0, 0, 0.05), 1)),
            kJacobianTolerance);
}

TEST(MncpJacobianTest, EdgeContactOnGround) {
  const auto box = geometry::MakeBox(Vector3d(0.25, 0.25, 0.05));
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.4, Vector3d::UnitX()));
  EXPECT_LT(JacobianError(MakeFixture(box, kGround, Q, Vector3d(0, 0, 0.2), 2)),
            kJacobianTolerance);
}

TEST(MncpJacobianTest, VertexContactOnTiltedPlane) {
  const auto box = geometry::MakeBox(Vector3d(0.2, 0.1, 0.05));
  const auto tilted = geometry::MakeHalfSpace(Vector3d(0.2, -0.1, 1.0), 0.05);
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()));
  EXPECT_LT(JacobianError(MakeFixture(box, tilted, Q, Vector3d(0.1, 0, 0.3), 3)),
            kJacobianTolerance);
}

TEST(MncpJacobianTest, FreeFlight) {
  const auto box = geometry::MakeBox(Vector3d(0.2, 0.1, 0.05));
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.3, Vector3d(0, 1, 1).normalized()));
  EXPECT_LT(JacobianError(MakeFixture(box, kGround, Q, Vector3d(0, 0, 1.0), 4, true)),
            kJacobianTolerance);
}

TEST(MncpJacobianTest, SmoothCylinderHull) {
  const auto cylinder = geometry::MakeCylinder(0.1, 0.3, 0);
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.2, Vector3d(0, 0, 1)));
  EXPECT_LT(JacobianError(MakeFixture(cylinder, kGround, Q, Vector3d(0, 0, 0.1), 5)),
            kJacobianTolerance);
}

TEST(MncpJacobianTest, BoxFixtureWithSeveralConstraints) {
  // G with six constraints: the contact normal then depends on l_G and the frame rotates with it
  auto fixture = geometry::MakeBox(Vector3d(0.5, 0.5, 0.5));
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.5, Vector3d(1, -1, 0).normalized()));
  EXPECT_LT(JacobianError(MakeFixture(geometry::MakeBox(Vector3d(0.1, 0.1, 0.1)), fixture, Q,
                                      Vector3d(0.1, 0.2, 0.7), 6)),
            kJacobianTolerance);
}

TEST(MncpJacobianTest, SmoothSphereObstacle) {
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.5, Vector3d(1, 2, 0).normalized()));
  EXPECT_LT(JacobianError(MakeFixture(geometry::MakeBox(Vector3d(0.1, 0.1, 0.1)),
                                      geometry::MakeSphere(1.0), Q, Vector3d(0, 0.1, 1.1), 7)),
            kJacobianTolerance);
}

}  // namespace
}  // namespace ecpsim::engine
