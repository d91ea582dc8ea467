// The camera: framing, clipping planes and errors at every scale.

#include "render/camera.h"

#include <cmath>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr int kWidth = 320, kHeight = 240;  // pixels
// pixel coordinates of the same scene at two scales agree up to the rounding of the matrices
constexpr double kPixelRounding = 1e-9;   // pixels
constexpr double kDepthRounding = 1e-12;  // NDC

// a body's bounding sphere and a fixed camera at the scale `L` (m)
std::vector<BoundingSphere> Spheres(double L) {
  return {{L * Eigen::Vector3d(0.1, -0.2, 0.3), 0.4 * L},
          {L * Eigen::Vector3d(-0.5, 0, 0.2), 0.1 * L}};
}

CameraSpec FixedSpec(double L) {
  CameraSpec spec;
  spec.automatic = false;
  spec.position = L * Eigen::Vector3d(1.4, -2.2, 1.3);
  spec.target = L * Eigen::Vector3d(0.1, 0, 0.1);
  return spec;
}

// Every point of the scene, scaled with it, lands on the same pixel at the same depth: the
// clipping planes scale with the scene (a 100 m far margin made depth in a millimetre scene
// coarse, and a 0.1 m smallest framing radius shrank a millimetre body to a dot).
TEST(Camera, ScaledSceneGivesTheSamePixelsAndDepths) {
  const std::vector<Eigen::Vector3d> points = {
      {0, 0, 0}, {0.3, -0.1, 0.05}, {-0.4, 0.2, 0.5}, {2, 3, 0}, {-1, -1, 0}};
  for (bool automatic : {true, false}) {
    CameraSpec metre = FixedSpec(1);
    metre.automatic = automatic;
    const Camera reference = MakeCamera(metre, Spheres(1), kWidth, kHeight);
    for (double L : {1e-3, 1e3}) {
      CameraSpec spec = FixedSpec(L);
      spec.automatic = automatic;
      const Camera scaled = MakeCamera(spec, Spheres(L), kWidth, kHeight);
      constexpr double kScaledRoundOff = 1e-12;  // relative: a few flops on scaled inputs
      EXPECT_NEAR(GroundHalfExtent(scaled), L * GroundHalfExtent(reference),
                  kScaledRoundOff * L * GroundHalfExtent(reference));
      for (const Eigen::Vector3d& p : points) {
        Eigen::Vector3d expected, actual;
        ASSERT_TRUE(reference.ToPixel(p, &expected));
        ASSERT_TRUE(scaled.ToPixel(L * p, &actual)) << "L = " << L;
        EXPECT_NEAR(actual.x(), expected.x(), kPixelRounding) << "L = " << L;
        EXPECT_NEAR(actual.y(), expected.y(), kPixelRounding) << "L = " << L;
        EXPECT_NEAR(actual.z(), expected.z(), kDepthRounding) << "L = " << L;
      }
    }
  }
}

// The far plane lies past the ground sheet's corners (a sheet of GroundHalfExtent around the
// point under the target) and past a body far behind the target.
TEST(Camera, FarPlaneHoldsTheGroundSheetAndEveryBody) {
  for (double L : {1e-3, 1.0, 1e3}) {
    std::vector<BoundingSphere> spheres = Spheres(L);
    spheres.push_back({L * Eigen::Vector3d(-40, 60, 0), L});  // far behind the target
    const Camera camera = MakeCamera(FixedSpec(L), spheres, kWidth, kHeight);
    const Eigen::Vector3d foot(camera.target.x(), camera.target.y(), 0);
    const double R = GroundHalfExtent(camera);
    int in_front = 0;  // corners behind the eye are clipped by the near plane anyway
    for (const Eigen::Vector3d& corner : {Eigen::Vector3d(R, R, 0), Eigen::Vector3d(R, -R, 0),
                                          Eigen::Vector3d(-R, R, 0), Eigen::Vector3d(-R, -R, 0)}) {
      Eigen::Vector3d pixel;
      if (camera.ToPixel(foot + corner, &pixel)) {
        ++in_front;
        EXPECT_LT(pixel.z(), 1) << "L = " << L;
      }
    }
    EXPECT_GE(in_front, 2);
    Eigen::Vector3d pixel;
    ASSERT_TRUE(camera.ToPixel(spheres.back().centre, &pixel));
    EXPECT_LT(pixel.z(), 1) << "L = " << L;
  }
}

TEST(Camera, EyeAtTheTargetIsAnInputErrorAtEveryScale) {
  CameraSpec spec = FixedSpec(1);
  spec.position = spec.target;
  EXPECT_THAT([&] { MakeCamera(spec, {}, kWidth, kHeight); },
              ThrowsMessage<InputError>(HasSubstr("equals target")));
  // the metre scene's camera scaled by 1e-10 is a camera, not a coincident eye and target
  EXPECT_NO_THROW(MakeCamera(FixedSpec(1e-10), {}, kWidth, kHeight));
}

}  // namespace
}  // namespace ecpsim::render
