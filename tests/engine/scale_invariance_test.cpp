// The engine is scale-free: a scene L times larger (Froude scaling, tests/engine/scaled_scene.h)
// follows the same dimensionless trajectory, from a 0.1 mm microrobot to a 1 km body.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"
#include "tests/engine/scaled_scene.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

// dimensionless (units of FroudeUnits: lengths in L, velocities in √L, rates in 1/√L): the
// solver stops at 1e-12 of each body's own scales whatever L is, so every step solves the same
// scaled problem and trajectories differ only by round-off (measured ≤ 4e-12, the T-bar);
// the bar leaves room for that round-off being amplified through impacts and contact-mode switches
constexpr double kSimilarityTolerance = 1e-9;

const double kScales[] = {1e-4, 1e-3, 1e-2, 1e-1, 10, 100, 1e3};

// the largest difference over the run between the scene at L = 1 and its copy at L, in the
// original's units: |Δp|, |Δv|, |Δω| · (1 + |ω|)⁻¹ and |ΔQ| (sign-aligned)
double LargestDifference(const Scene& scene, double L) {
  const Scene scaled = testing::ScaledScene(scene, L);
  State a = InitialState(scene), b = InitialState(scaled);
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  double largest = 0;
  for (int k = 0; k < steps; ++k) {
    Step(scene, a);
    Step(scaled, b);
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
      const BodyState& x = a.bodies[i];
      const BodyState y = testing::InOriginalUnits(b.bodies[i], L);
      const double dq = std::min((x.Q_WB.coeffs() - y.Q_WB.coeffs()).norm(),
                                 (x.Q_WB.coeffs() + y.Q_WB.coeffs()).norm());
      largest = std::max({largest, (x.p_WB - y.p_WB).norm(), (x.v_WB - y.v_WB).norm(),
                          (x.w_WB - y.w_WB).norm() / (1 + x.w_WB.norm()), dq});
    }
  }
  return largest;
}

void ExpectSimilarAtEveryScale(const Scene& scene, const char* name) {
  for (const double L : kScales) {
    double difference = INFINITY;
    // a SolverFailure at any scale fails the test with its message
    EXPECT_NO_THROW(difference = LargestDifference(scene, L)) << name << ", L = " << L;
    std::printf("%s, L = %g: largest dimensionless difference %.3g\n", name, L, difference);
    EXPECT_LE(difference, kSimilarityTolerance) << name << ", L = " << L;
  }
}

TEST(ScaleInvarianceTest, SlideAndSpin) {
  // a flat box sliding at 0.5 m/s and turning at 2 rad/s until friction stops both
  Body box = testing::MakeBoxBody(Vector3d(0.5, 0.5, 0.1), 15);
  box.p0 = Vector3d(0, 0, 0.05);
  box.v0 = Vector3d(0.5, 0.2, 0);
  box.w0 = Vector3d(0, 0, 2);
  Scene scene = testing::MakeGroundScene({box});
  scene.duration = 1;
  ExpectSimilarAtEveryScale(scene, "slide and spin");
}

TEST(ScaleInvarianceTest, TiltedDrop) {
  // a box dropped corner first while spinning: impacts, tipping and settling on a face
  Body box = testing::MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 2);
  box.p0 = Vector3d(0, 0, 0.3);
  box.q0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()));
  box.v0 = Vector3d(0.5, 0, 0);
  box.w0 = Vector3d(0, 0, 2);
  Scene scene = testing::MakeGroundScene({box});
  scene.duration = 1;
  ExpectSimilarAtEveryScale(scene, "tilted drop");
}

TEST(ScaleInvarianceTest, PaperDesk) {
  ExpectSimilarAtEveryScale(testing::PaperDeskScene(ContactModel::kHull), "desk");
}

TEST(ScaleInvarianceTest, PaperTBar) {
  // the T-bar's wobbles between one-, two-point and face contact, and its slide (scenes/tbar.yaml)
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/tbar.yaml").scene;
  ExpectSimilarAtEveryScale(scene, "T-bar");
}

}  // namespace
}  // namespace ecpsim::engine
