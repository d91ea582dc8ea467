#include "geometry/mesh_topology.h"

#include <gtest/gtest.h>

#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using testing::MakeBoxMesh;
using testing::MakeUnitTetrahedron;

TEST(MeshTopologyTest, BoxIsClosedAndOriented) {
  const MeshTopology t =
      AnalyzeTopology(MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.consistently_oriented);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.non_manifold_edges, 0);
}

TEST(MeshTopologyTest, BoxWithoutAFaceHasFourBoundaryEdges) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 3));
  mesh.triangles.resize(10);  // drop the +z quad
  const MeshTopology t = AnalyzeTopology(mesh);
  EXPECT_FALSE(t.closed);
  EXPECT_TRUE(t.consistently_oriented);
  EXPECT_EQ(t.boundary_edges, 4);
  EXPECT_EQ(t.non_manifold_edges, 0);
}

TEST(MeshTopologyTest, FlippedTriangleIsInconsistent) {
  TriangleMesh mesh = MakeUnitTetrahedron();
  std::swap(mesh.triangles[3][0], mesh.triangles[3][1]);
  const MeshTopology t = AnalyzeTopology(mesh);
  EXPECT_TRUE(t.closed);
  EXPECT_FALSE(t.consistently_oriented);
}

TEST(MeshTopologyTest, TwoTetrahedraOnOneEdgeAreNonManifold) {
  // the second tetrahedron is the first rotated by π about the z axis: they share only the
  // edge (0, e_z), which four triangles then use
  TriangleMesh mesh = MakeUnitTetrahedron();
  mesh.vertices.emplace_back(-1, 0, 0);
  mesh.vertices.emplace_back(0, -1, 0);
  for (const Eigen::Vector3i& t : MakeUnitTetrahedron().triangles) {
    Eigen::Vector3i u = t;
    for (int c = 0; c < 3; ++c) u[c] = u[c] == 1 ? 4 : (u[c] == 2 ? 5 : u[c]);
    mesh.triangles.push_back(u);
  }
  const MeshTopology t = AnalyzeTopology(mesh);
  EXPECT_FALSE(t.closed);
  EXPECT_TRUE(t.consistently_oriented);
  EXPECT_EQ(t.non_manifold_edges, 1);
  EXPECT_EQ(t.boundary_edges, 0);
}

TEST(MeshTopologyTest, SingleTriangleAndEmptyMesh) {
  TriangleMesh triangle;
  triangle.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.triangles = {{0, 1, 2}};
  const MeshTopology t = AnalyzeTopology(triangle);
  EXPECT_FALSE(t.closed);
  EXPECT_EQ(t.boundary_edges, 3);
  EXPECT_FALSE(AnalyzeTopology(TriangleMesh{}).closed);
}

TEST(MeshTopologyTest, SameDirectionTwiceIsInconsistentEvenWhenOpen) {
  // two triangles sharing edge (0, 1) traversed 0→1 by both
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}};
  const MeshTopology t = AnalyzeTopology(mesh);
  EXPECT_FALSE(t.consistently_oriented);
  EXPECT_EQ(t.boundary_edges, 4);
}

}  // namespace
}  // namespace ecpsim::geometry
