// The display triangulation of polyhedral hulls: closed, outward-wound, area-preserving, and
// without the long slivers of a fan on faces with many corners.

#include <cmath>
#include <map>
#include <utility>

#include <gtest/gtest.h>

#include "geometry/convex_hull.h"
#include "render/frame_input.h"

namespace ecpsim::render {
namespace {

constexpr int kSides = 64;

// a regular 64-gon prism, circumradius 1 m, height 1 m, axis z from z = 0 to 1
geometry::ConvexHull Prism() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < kSides; ++i) {
    const double angle = 2 * M_PI * i / kSides;
    for (double z : {0.0, 1.0}) points.emplace_back(std::cos(angle), std::sin(angle), z);
  }
  return geometry::ComputeConvexHull(points, "prism");
}

Eigen::Vector3d Corner(const geometry::TriangleMesh& mesh, int i) { return mesh.vertices[i]; }

TEST(HullGeometry, FacesAreTriangulatedClosedAndOutward) {
  const geometry::ConvexHull hull = Prism();
  const HullGeometry display = MakeHullGeometry(hull);
  // n − 2 triangles per n-gon face: 2 caps of 62 and 64 side rectangles of 2
  ASSERT_EQ(display.mesh.triangles.size(), static_cast<size_t>(2 * (kSides - 2) + 2 * kSides));
  // every directed edge meets its opposite exactly once: the surface is closed and consistently
  // wound
  std::map<std::pair<int, int>, int> directed;
  // m³: below the smallest ear's 4.7e-4 (below), far above a degenerate ear's round-off
  constexpr double kSmallestEar = 1e-4;
  double area = 0;
  const Eigen::Vector3d centre(0, 0, 0.5);
  for (const auto& t : display.mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    const Eigen::Vector3d a = Corner(display.mesh, t[0]), b = Corner(display.mesh, t[1]);
    const Eigen::Vector3d c = Corner(display.mesh, t[2]);
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    // outward: the normal points away from the prism's centre; no ear is degenerate (the
    // smallest, on a cap, has area sin(2π/64)(1 − cos(2π/64)) ≈ 4.7e-4 m², and its normal's
    // dot product with the half-height offset 0.5 m is that area again)
    EXPECT_GT(normal.dot((a + b + c) / 3 - centre), kSmallestEar);
    area += 0.5 * normal.norm();
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  // the surface area in closed form: two caps of ½ n sin(2π/n) and n sides of 2 sin(π/n) × 1;
  // sums of ~250 double areas agree to ~1e-13 m²
  constexpr double kAreaSumRoundOff = 1e-10;  // m²
  const double expected =
      kSides * std::sin(2 * M_PI / kSides) + 2 * kSides * std::sin(M_PI / kSides);
  EXPECT_NEAR(area, expected, kAreaSumRoundOff);
}

TEST(HullGeometry, ManyCorneredFacesHaveShortDiagonals) {
  const HullGeometry display = MakeHullGeometry(Prism());
  // the top cap's diagonals: (sum of its triangles' perimeters − the cap's perimeter) / 2. Ears
  // cut round by round add at most one perimeter (2π) of diagonals per round, log2(64) rounds
  // at most; a fan from one corner would add Σ 2 sin(πk/64), k = 2..62, ≈ 81 m
  double perimeters = 0;
  for (const auto& t : display.mesh.triangles) {
    const Eigen::Vector3d a = Corner(display.mesh, t[0]), b = Corner(display.mesh, t[1]);
    const Eigen::Vector3d c = Corner(display.mesh, t[2]);
    if (a.z() < 1 || b.z() < 1 || c.z() < 1) continue;
    perimeters += (b - a).norm() + (c - b).norm() + (a - c).norm();
  }
  const double cap_perimeter = 2 * kSides * std::sin(M_PI / kSides);
  const double diagonals = 0.5 * (perimeters - cap_perimeter);
  EXPECT_GT(diagonals, 0);
  EXPECT_LT(diagonals, 2 * M_PI * std::log2(kSides));
}

}  // namespace
}  // namespace ecpsim::render
