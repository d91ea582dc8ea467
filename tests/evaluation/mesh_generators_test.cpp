// The drop sweep's generated meshes: closed, outward-wound solids of the promised shape, the
// same for the same seed.

#include "evaluation/mesh_generators.h"

#include <algorithm>
#include <numeric>
#include <set>
#include <utility>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "geometry/convex_hull.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_topology.h"
#include "geometry/weld_vertices.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::Vector3d;
using geometry::TriangleMesh;

constexpr int kSeedsPerKind = 12;
// dimensionless: sums of a few thousand products of unit-sized coordinates
constexpr double kRoundOff = 1e-12;

// signed volume of the closed mesh: positive when its triangles wind outward
double SignedVolume(const TriangleMesh& mesh) {
  double volume = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6;
  }
  return volume;
}

Vector3d Extent(const TriangleMesh& mesh) {
  Vector3d lo = Vector3d::Constant(INFINITY), hi = Vector3d::Constant(-INFINITY);
  for (const Vector3d& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return hi - lo;
}

// connected components of the triangles (shared vertices join them)
int Components(const TriangleMesh& mesh) {
  std::vector<int> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    parent[root(t[0])] = root(t[1]);
    parent[root(t[1])] = root(t[2]);
  }
  std::set<int> roots;
  for (const Eigen::Vector3i& t : mesh.triangles) roots.insert(root(t[0]));
  return static_cast<int>(roots.size());
}

// V − E + F of the closed mesh: 2 per sphere-like component, 0 for a torus
int EulerCharacteristic(const TriangleMesh& mesh) {
  std::set<std::pair<int, int>> edges;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      edges.insert(std::minmax(t[c], t[(c + 1) % 3]));
    }
  }
  return static_cast<int>(mesh.vertices.size()) - static_cast<int>(edges.size()) +
         static_cast<int>(mesh.triangles.size());
}

class EveryKind : public ::testing::TestWithParam<MeshKind> {};

TEST_P(EveryKind, ClosedOutwardUnitSizedSolids) {
  for (int seed = 0; seed < kSeedsPerKind; ++seed) {
    SCOPED_TRACE(::testing::Message() << MeshKindName(GetParam()) << " seed " << seed);
    const GeneratedMesh g = GenerateMesh(GetParam(), seed);
    const geometry::MeshTopology topology = geometry::AnalyzeTopology(g.mesh);
    EXPECT_TRUE(topology.closed);
    EXPECT_TRUE(topology.consistently_oriented);
    EXPECT_EQ(topology.non_manifold_edges, 0);
    EXPECT_GT(SignedVolume(g.mesh), 0);
    // the mass-property checks a mesh file gets (closed, wound, not flat) pass at size 1
    EXPECT_NO_THROW(geometry::ComputeMassProperties(g.mesh, 1000));
    EXPECT_NEAR(Extent(g.mesh).norm(), 1, kRoundOff);
    // no two vertices so close that loading the mesh from a file would weld them
    EXPECT_EQ(
        geometry::WeldVertices(g.mesh, geometry::DefaultWeldTolerance(g.mesh)).vertices.size(),
        g.mesh.vertices.size());
    EXPECT_FALSE(g.description.empty());
    EXPECT_EQ(g.description.find(','), std::string::npos) << "descriptions go into CSV fields";
  }
}

TEST_P(EveryKind, SameSeedSameMeshOtherSeedOtherMesh) {
  const GeneratedMesh a = GenerateMesh(GetParam(), 7), b = GenerateMesh(GetParam(), 7);
  ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
  for (size_t i = 0; i < a.mesh.vertices.size(); ++i) {
    EXPECT_EQ(a.mesh.vertices[i], b.mesh.vertices[i]);
  }
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  EXPECT_EQ(a.description, b.description);
  EXPECT_NE(GenerateMesh(GetParam(), 8).description, a.description);
}

TEST_P(EveryKind, OneComponentOfTheRightGenusOrSeparateParts) {
  for (int seed = 0; seed < kSeedsPerKind; ++seed) {
    const GeneratedMesh g = GenerateMesh(GetParam(), seed);
    const int components = Components(g.mesh);
    if (GetParam() == MeshKind::kDisconnected) {
      EXPECT_TRUE(components == 2 || components == 3) << components;
      EXPECT_EQ(EulerCharacteristic(g.mesh), 2 * components);
    } else {
      EXPECT_EQ(components, 1);
      EXPECT_EQ(EulerCharacteristic(g.mesh), GetParam() == MeshKind::kTorus ? 0 : 2);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(MeshGenerators, EveryKind, ::testing::ValuesIn(AllMeshKinds()),
                         [](const auto& param_info) {
                           return std::string(MeshKindName(param_info.param));
                         });

TEST(MeshGeneratorsTest, ConvexPolytopesAreTheirOwnHulls) {
  for (int seed = 0; seed < kSeedsPerKind; ++seed) {
    const GeneratedMesh g = GenerateMesh(MeshKind::kConvex, seed);
    const TriangleMesh hull =
        geometry::TriangulateHull(geometry::ComputeConvexHull(g.mesh.vertices));
    EXPECT_EQ(hull.vertices.size(), g.mesh.vertices.size());
    // the hull merges faces whose planes agree to kCoplanarTolerance and fans them anew: the
    // two triangulations of such a face bound volumes that differ by less than that × its area,
    // and the whole surface of a diagonal-1 polytope is below π (the sphere's)
    EXPECT_NEAR(SignedVolume(hull), SignedVolume(g.mesh), geometry::kCoplanarTolerance * 3.15);
  }
}

TEST(MeshGeneratorsTest, LTAndUShapesLackAtLeastTheirCutOutOfTheBox) {
  // the smallest cut-outs the parameter ranges allow, as fractions of the bounding box: L a
  // corner ≥ 0.5 × 0.5, T two corners ≥ 0.5 × 0.5 together, U a slot ≥ 0.2 × 0.4
  const std::pair<MeshKind, double> kinds[] = {
      {MeshKind::kLShape, 0.25}, {MeshKind::kTShape, 0.25}, {MeshKind::kUShape, 0.08}};
  for (const auto& [kind, cut] : kinds) {
    for (int seed = 0; seed < kSeedsPerKind; ++seed) {
      const GeneratedMesh g = GenerateMesh(kind, seed);
      const Vector3d extent = Extent(g.mesh);
      EXPECT_LE(SignedVolume(g.mesh), (1 - cut) * extent.prod()) << MeshKindName(kind);
    }
  }
}

TEST(MeshGeneratorsTest, PlatesAndNeedlesAreHundredToOne) {
  for (int seed = 0; seed < kSeedsPerKind; ++seed) {
    // the plate's thickness is 1/100 of its outline's ellipse, which the polygon's extent
    // reaches to within its jittered corners (≥ half the ellipse's width for a triangle)
    Vector3d plate = Extent(GenerateMesh(MeshKind::kPlate, seed).mesh);
    std::sort(plate.data(), plate.data() + 3);
    EXPECT_GE(plate[0] / plate[2], 1.0 / 100 - kRoundOff);
    EXPECT_LE(plate[0] / plate[2], 2.0 / 100);
    // the needle's section fits in a circle of 1/100 of its length
    Vector3d needle = Extent(GenerateMesh(MeshKind::kNeedle, seed).mesh);
    std::sort(needle.data(), needle.data() + 3);
    EXPECT_LE(needle[1] / needle[2], 1.0 / 100 + kRoundOff);
    EXPECT_GE(needle[1] / needle[2], 1.0 / 400);
  }
}

TEST(MeshGeneratorsTest, NearlyCoplanarBoxesAreBoxesToTheirJitter) {
  // every vertex moves at most the largest jitter, which changes the volume by at most that
  // times the box's area, and its bounding box by twice that along each axis
  constexpr double kMaxJitter = 1e-5;  // × diagonal, the generator's largest
  for (int seed = 0; seed < kSeedsPerKind; ++seed) {
    const GeneratedMesh g = GenerateMesh(MeshKind::kCoplanar, seed);
    const Vector3d e = Extent(g.mesh);
    const double area = 2 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
    EXPECT_NEAR(SignedVolume(g.mesh), e.prod(), 3 * kMaxJitter * area);
    EXPECT_GE(g.mesh.triangles.size(), 6u * 2 * 4 * 4) << "faces cut into at least 4 x 4 quads";
  }
}

TEST(MeshGeneratorsTest, NamesAreDistinct) {
  std::set<std::string> names;
  for (MeshKind kind : AllMeshKinds()) names.insert(MeshKindName(kind));
  EXPECT_EQ(names.size(), static_cast<size_t>(kMeshKindCount));
  EXPECT_EQ(names.count("unknown"), 0u);
}

}  // namespace
}  // namespace ecpsim::evaluation
