#include "geometry/weld_vertices.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "geometry/mesh_topology.h"
#include "tests/geometry/test_meshes.h"
#include "tests/tolerances.h"

namespace ecpsim::geometry {
namespace {

using testing::MakeBoxMesh;

// the mesh with every triangle's corners stored separately, as STL files do
TriangleMesh ToSoup(const TriangleMesh& mesh) {
  TriangleMesh soup;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int c = 0; c < 3; ++c) soup.vertices.push_back(mesh.vertices[t[c]]);
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  return soup;
}

TEST(WeldVerticesTest, SoupOfABoxBecomesAClosedBox) {
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(-1, 0, 2), Eigen::Vector3d(0, 2, 5));
  const TriangleMesh welded = WeldVertices(ToSoup(box), DefaultWeldTolerance(box));
  EXPECT_EQ(welded.vertices.size(), 8u);
  EXPECT_EQ(welded.triangles.size(), 12u);
  const MeshTopology topology = AnalyzeTopology(welded);
  EXPECT_TRUE(topology.closed);
  EXPECT_TRUE(topology.consistently_oriented);
  // triangle corners keep their positions and order
  for (std::size_t t = 0; t < box.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(welded.vertices[welded.triangles[t][c]], box.vertices[box.triangles[t][c]]);
    }
  }
}

TEST(WeldVerticesTest, DefaultToleranceIsAFractionOfTheDiagonal) {
  // box 1 × 2 × 3: diagonal √14; the stated fraction is 1e-7
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 3));
  constexpr double kToleranceRoundOff = 1e-22;  // m: two ulps of the 3.7e-7 m tolerance
  EXPECT_NEAR(DefaultWeldTolerance(box), 1e-7 * std::sqrt(14.0), kToleranceRoundOff);
  EXPECT_EQ(DefaultWeldTolerance(TriangleMesh{}), 0.0);
}

TEST(WeldVerticesTest, DefaultToleranceStaysFiniteForHugeAndTinyMeshes) {
  // the squared diagonal of a 1e200 m box overflows (that aborted `ecpsim hull --scale 1e200`),
  // that of a 1e-200 m box underflows to 0; the tolerance itself is representable in both
  for (double size : {1e200, 1e-200}) {
    const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 3) * size);
    EXPECT_NEAR(DefaultWeldTolerance(box) / (1e-7 * std::sqrt(14.0) * size), 1.0, kUnitRoundOff)
        << size;
  }
}

TEST(WeldVerticesTest, MergesWithinToleranceAcrossCellFaces) {
  // 2000 random points, each followed by a copy displaced by 0.9 tolerance in a random direction
  // (the grid cell is 16 tolerances, so about one pair in twelve, 0.9 × 1.5 / 16, straddles a
  // cell face and exercises the neighbour search), then by a copy
  // displaced by 2 tolerances that must stay separate; the points are ≥ 1e-3 apart
  const double tolerance = 1e-6;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::normal_distribution<double> gaussian;
  TriangleMesh mesh;
  int pairs = 0;
  while (pairs < 2000) {
    const Eigen::Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    bool isolated = true;
    for (std::size_t i = 0; i < mesh.vertices.size() && isolated; i += 3) {
      isolated = (mesh.vertices[i] - p).norm() > 1e-3;
    }
    if (!isolated) continue;
    const Eigen::Vector3d direction =
        Eigen::Vector3d(gaussian(rng), gaussian(rng), gaussian(rng)).normalized();
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(p);
    mesh.vertices.push_back(p + 0.9 * tolerance * direction);
    mesh.vertices.push_back(p - 2.0 * tolerance * direction);
    // triangle (p, p', p''): p and p' merge, so it is degenerate and dropped
    mesh.triangles.emplace_back(base, base + 1, base + 2);
    ++pairs;
  }
  const TriangleMesh welded = WeldVertices(mesh, tolerance);
  EXPECT_EQ(welded.vertices.size(), 2u * pairs);
  EXPECT_TRUE(welded.triangles.empty());
}

TEST(WeldVerticesTest, ZeroToleranceMergesExactDuplicatesOnly) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1e-300, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  const TriangleMesh welded = WeldVertices(mesh, 0.0);
  EXPECT_EQ(welded.vertices.size(), 4u);
  ASSERT_EQ(welded.triangles.size(), 2u);
  EXPECT_EQ(welded.triangles[1], Eigen::Vector3i(1, 3, 2));
}

TEST(WeldVerticesTest, DropsTrianglesThatCollapse) {
  // a sliver whose two corners lie 1e-9 apart collapses at tolerance 1e-8; the other survives
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1e-9, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}};
  const TriangleMesh welded = WeldVertices(mesh, 1e-8);
  EXPECT_EQ(welded.vertices.size(), 3u);
  ASSERT_EQ(welded.triangles.size(), 1u);
  EXPECT_EQ(welded.triangles[0], Eigen::Vector3i(0, 1, 2));
}

}  // namespace
}  // namespace ecpsim::geometry
