// `parts:` of a body in the scene format: primitives and convex meshes, placed by `at` and
// `rpy` in the body's mesh frame, inside its hull (docs/scene_format.md, "Parts").

#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"

namespace ecpsim::engine {
namespace {

const std::string kFixtures = std::string(ECPSIM_SOURCE_DIR) + "/tests/fixtures/meshes";

// a 4 × 4 × 6 m box body (its frame its centre) with `parts`
LoadedScene WithParts(const std::string& parts) {
  const std::string yaml = fmt::format(
      "duration: 1\nground: {{}}\nbodies:\n"
      "  - {{name: b, shape: {{box: {{size: [4, 4, 6]}}}}, mass: 1, position: [0, 0, 3], "
      "parts: {}}}\n",
      parts);
  return LoadSceneText(yaml, "parts.yaml", kFixtures);
}

std::string ErrorOf(const std::string& parts) {
  try {
    WithParts(parts);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SceneYamlPartsTest, AMeshPartIsItsFilesHullWhereTheFileHasIt) {
  // box.obj spans [0, 1] × [0, 2] × [0, 3]: the same as a box part of that size centred there
  const Scene scene = WithParts(
                          "[{mesh: box.obj}, {box: {size: [1, 2, 3]}, at: [0.5, 1, 1.5]}, "
                          "{mesh: box.obj, at: [-1, -2, -3]}]")
                          .scene;
  const auto& parts = scene.bodies[0].parts;
  ASSERT_EQ(parts.size(), 3u);
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(-1, 0.5, -2)}) {
    EXPECT_TRUE((parts[0]->Support(d) - parts[1]->Support(d)).norm() < 1e-15) << d.transpose();
    // `at` moves the file's frame
    EXPECT_TRUE(
        (parts[2]->Support(d) - (parts[0]->Support(d) + Eigen::Vector3d(-1, -2, -3))).norm() <
        1e-15);
  }
  EXPECT_EQ(scene.bodies[0].decomposition, Decomposition::kParts);
}

TEST(SceneYamlPartsTest, ASmoothPartIsTurnedAndPlaced) {
  // a cylinder along z turned by 90° about y lies along x
  const Scene scene =
      WithParts("[{cylinder: {radius: 0.5, length: 2}, at: [0.5, 0, 1], rpy: [0, 90, 0]}]").scene;
  const auto& part = *scene.bodies[0].parts[0];
  EXPECT_NEAR(part.Support(Eigen::Vector3d::UnitX()).x(), 1.5, 1e-15);
  EXPECT_NEAR(part.Support(-Eigen::Vector3d::UnitX()).x(), -0.5, 1e-15);
  EXPECT_NEAR(part.Support(Eigen::Vector3d::UnitZ()).z(), 1.5, 1e-15);
  EXPECT_NEAR(part.Support(Eigen::Vector3d::UnitY()).y(), 0.5, 1e-15);
  // its constraints: inside at its centre, on its side at radius, its gradient turned
  EXPECT_LT(part.Value(0, Eigen::Vector3d(0.5, 0, 1)), 0);
  int side = 0;
  while (part.IsLinear(side)) ++side;
  EXPECT_NEAR(part.Value(side, Eigen::Vector3d(0.5, 0, 1.5)), 0, 1e-15);
  EXPECT_TRUE(
      (part.Gradient(side, Eigen::Vector3d(0.5, 0, 1.5)) - Eigen::Vector3d::UnitZ()).norm() <
      1e-15);
  EXPECT_TRUE(scene.bodies[0].parts[0]->AsPolyhedron() == nullptr);
}

TEST(SceneYamlPartsTest, APartOutsideTheHullOrOfTwoShapesIsRejected) {
  EXPECT_NE(ErrorOf("[{sphere: {radius: 1}, at: [1.5, 0, 0]}]")
                .find("bodies[0].parts[0] = {sphere: {radius: 1}, at: [1.5, 0, 0]}: expected a "
                      "part inside the body; its point (2.5, 0, 0) m (mesh frame) lies 0.5 m "
                      "outside the body's hull"),
            std::string::npos)
      << ErrorOf("[{sphere: {radius: 1}, at: [1.5, 0, 0]}]");
  EXPECT_NE(ErrorOf("[{sphere: {radius: 1}, box: {size: [1, 1, 1]}}]")
                .find("exactly one of box, sphere, cylinder, ellipsoid or mesh"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[{mesh: no_such.obj}]").find("bodies[0].parts[0].mesh"), std::string::npos);
}

}  // namespace
}  // namespace ecpsim::engine
