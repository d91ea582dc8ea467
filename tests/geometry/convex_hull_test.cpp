#include "geometry/convex_hull.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "geometry/mesh_io.h"
#include "geometry/paper_bodies.h"
#include "tests/tolerances.h"

namespace ecpsim::geometry {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// unit-scale coordinates: a dot product n · p carries a few 1e-16 of round-off
constexpr double kRoundOff = 1e-12;

// m: a face's corners lie within the merge tolerance (kCoplanarTolerance, 1e-6 × the diagonal)
// of its plane; 1e-5 covers the unit-size point sets here with room
constexpr double kCornerOffPlane = 1e-5;

int CountEdges(const ConvexHull& hull) {
  std::set<std::pair<int, int>> edges;
  for (const auto& polygon : hull.faces) {
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const int a = polygon[k];
      const int b = polygon[(k + 1) % polygon.size()];
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  }
  return static_cast<int>(edges.size());
}

// every structural invariant of ConvexHull, and that `points` satisfy every inequality
void ExpectValidHull(const ConvexHull& hull, const std::vector<Eigen::Vector3d>& points) {
  const int v = static_cast<int>(hull.vertices.size());
  const int f = static_cast<int>(hull.faces.size());
  ASSERT_EQ(hull.normals.size(), hull.faces.size());
  ASSERT_EQ(hull.offsets.size(), hull.faces.size());
  ASSERT_EQ(hull.vertex_faces.size(), hull.vertices.size());
  ASSERT_EQ(hull.vertex_neighbors.size(), hull.vertices.size());
  // Euler's formula for a convex polyhedron
  EXPECT_EQ(v - CountEdges(hull) + f, 2);
  for (int i = 0; i < f; ++i) {
    EXPECT_NEAR(hull.normals[i].norm(), 1.0, kUnitRoundOff);
    ASSERT_GE(hull.faces[i].size(), 3u);
    // counter-clockwise seen from outside: the polygon's area vector points along the normal
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    const auto& polygon = hull.faces[i];
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      area += hull.vertices[polygon[k]].cross(hull.vertices[polygon[(k + 1) % polygon.size()]]);
    }
    EXPECT_GT(area.dot(hull.normals[i]), 0.0) << "face " << i;
    // the face's corners lie on its plane (within the merge tolerance of a unit-size set)
    for (int corner : polygon) {
      EXPECT_NEAR(hull.normals[i].dot(hull.vertices[corner]), hull.offsets[i], kCornerOffPlane);
    }
  }
  for (int j = 0; j < v; ++j) {
    EXPECT_GE(hull.vertex_faces[j].size(), 3u) << "vertex " << j;
    EXPECT_TRUE(std::is_sorted(hull.vertex_faces[j].begin(), hull.vertex_faces[j].end()));
    for (int face : hull.vertex_faces[j]) {
      const auto& polygon = hull.faces[face];
      EXPECT_NE(std::find(polygon.begin(), polygon.end(), j), polygon.end());
    }
  }
  double worst = -1;
  for (const Eigen::Vector3d& p : points) {
    for (int i = 0; i < f; ++i) worst = std::max(worst, hull.normals[i].dot(p) - hull.offsets[i]);
  }
  EXPECT_LE(worst, kRoundOff);
}

// the hull of `points` shuffled into `orders` orders (seeded), every array bit for bit `expected`
void ExpectTheSameHullInEveryOrder(std::vector<Eigen::Vector3d> points, const ConvexHull& expected,
                                   int orders, unsigned seed) {
  std::mt19937 rng(seed);
  for (int order = 0; order < orders; ++order) {
    std::shuffle(points.begin(), points.end(), rng);
    const ConvexHull again = ComputeConvexHull(points, "shuffled points");
    EXPECT_EQ(again.vertices, expected.vertices) << "order " << order;
    EXPECT_EQ(again.faces, expected.faces) << "order " << order;
    EXPECT_EQ(again.normals, expected.normals) << "order " << order;
    EXPECT_EQ(again.offsets, expected.offsets) << "order " << order;
    EXPECT_EQ(again.vertex_faces, expected.vertex_faces) << "order " << order;
    EXPECT_EQ(again.vertex_neighbors, expected.vertex_neighbors) << "order " << order;
  }
}

std::vector<Eigen::Vector3d> BoxCorners(const Eigen::Vector3d& centre,
                                        const Eigen::Vector3d& half) {
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k) {
    corners.push_back(centre + half.cwiseProduct(Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1,
                                                                 k & 4 ? 1 : -1)));
  }
  return corners;
}

TEST(ConvexHullTest, BoxHasSixFacesWithExactNormalsAndOffsets) {
  const Eigen::Vector3d centre(0.1, -0.2, 0.05);
  const Eigen::Vector3d half(0.3, 0.2, 0.1);
  std::vector<Eigen::Vector3d> points = BoxCorners(centre, half);
  // interior points and points in the middle of faces and edges are no corners
  points.push_back(centre);
  points.push_back(centre + Eigen::Vector3d(half.x(), 0, 0));
  points.push_back(centre + Eigen::Vector3d(half.x(), half.y(), 0));
  const ConvexHull hull = ComputeConvexHull(points, "box");
  ASSERT_EQ(hull.faces.size(), 6u);
  EXPECT_EQ(hull.vertices.size(), 8u);
  ExpectValidHull(hull, points);
  int matched = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      const Eigen::Vector3d n = sign * Eigen::Vector3d::Unit(axis);
      for (std::size_t i = 0; i < hull.faces.size(); ++i) {
        if ((hull.normals[i] - n).norm() > kRoundOff) continue;
        ++matched;
        EXPECT_NEAR(hull.offsets[i], n.dot(centre) + half[axis], kRoundOff);
        EXPECT_EQ(hull.faces[i].size(), 4u);
      }
    }
  }
  EXPECT_EQ(matched, 6);
  for (int j = 0; j < 8; ++j) {
    EXPECT_EQ(hull.vertex_faces[j].size(), 3u);
    EXPECT_EQ(hull.vertex_neighbors[j].size(), 3u);
  }
}

// the unit cube rotated by R about its centre, moved to `centre`, sampled on a grid of
// cells × cells squares per face and rounded to float
std::vector<Eigen::Vector3d> FloatRoundedCubeGrid(const Eigen::Matrix3d& R,
                                                  const Eigen::Vector3d& centre, int cells) {
  std::vector<Eigen::Vector3d> points;
  for (int axis = 0; axis < 3; ++axis) {
    for (double side : {-0.5, 0.5}) {
      for (int i = 0; i <= cells; ++i) {
        for (int j = 0; j <= cells; ++j) {
          Eigen::Vector3d local;
          local[axis] = side;
          local[(axis + 1) % 3] = -0.5 + static_cast<double>(i) / cells;
          local[(axis + 2) % 3] = -0.5 + static_cast<double>(j) / cells;
          const Eigen::Vector3d exact = R * local + centre;
          points.push_back(exact.cast<float>().cast<double>());
        }
      }
    }
  }
  return points;
}

// A rotated cube sampled on a 5 × 5 grid per face and rounded to float, as a modelling tool's
// export would be: the face points are no longer exactly coplanar, yet the hull has 6 faces.
TEST(ConvexHullTest, FloatRoundedCubeStillHasSixFaces) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  const std::vector<Eigen::Vector3d> points =
      FloatRoundedCubeGrid(R, Eigen::Vector3d(2.0, -1.0, 0.5), 4);
  // the rounding really moves points off their planes (by up to ~1e-7 m here): by more than
  // 1e-9 m, far above double round-off
  constexpr double kFloatRoundingShows = 1e-9;  // m
  double largest_offset = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d local = R.transpose() * (p - Eigen::Vector3d(2.0, -1.0, 0.5));
    largest_offset = std::max(largest_offset, std::abs(local.cwiseAbs().maxCoeff() - 0.5));
  }
  EXPECT_GT(largest_offset, kFloatRoundingShows);
  const ConvexHull hull = ComputeConvexHull(points, "float cube");
  ASSERT_EQ(hull.faces.size(), 6u);
  EXPECT_EQ(hull.vertices.size(), 8u);
  ExpectValidHull(hull, points);
  // normals agree with the rotated axes to the float rounding (≤ 1e-6 rad over a 1 m face)
  constexpr double kFloatNormalError = 1e-6;
  for (const Eigen::Vector3d& n : hull.normals) {
    EXPECT_NEAR((R.transpose() * n).cwiseAbs().maxCoeff(), 1.0, kFloatNormalError);
  }
}

// The same through a file (FORMULATION trap 8): a rotated cube with 4 × 4 quads per face saved
// as binary STL stores float32 coordinates; loaded back, its hull still has 6 faces.
TEST(ConvexHullTest, CubeReadFromABinaryStlHasSixFaces) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  TriangleMesh cube;
  const auto node = [&](int axis, double side, int i, int j) {
    Eigen::Vector3d local;
    local[axis] = side;
    local[(axis + 1) % 3] = -0.05 + 0.025 * i;
    local[(axis + 2) % 3] = -0.05 + 0.025 * j;
    cube.vertices.push_back(R * local + Eigen::Vector3d(0.3, 0.1, 0.7));
    return static_cast<int>(cube.vertices.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (double side : {-0.05, 0.05}) {
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          const int a = node(axis, side, i, j);
          const int b = node(axis, side, i + 1, j);
          const int c = node(axis, side, i + 1, j + 1);
          const int d = node(axis, side, i, j + 1);
          // outward winding: (b − a) × (d − a) points along +axis
          if (side > 0) {
            cube.triangles.emplace_back(a, b, c);
            cube.triangles.emplace_back(a, c, d);
          } else {
            cube.triangles.emplace_back(a, c, b);
            cube.triangles.emplace_back(a, d, c);
          }
        }
      }
    }
  }
  const std::string path = std::string(ECPSIM_BINARY_DIR) + "/convex_hull_test_rotated_cube.stl";
  SaveMesh(cube, path);
  const TriangleMesh loaded = LoadMesh(path);
  // float32 rounding moved the face points off their planes (by ~1e-8 m here): by more than
  // 1e-10 m, far above double round-off
  constexpr double kFloatRoundingShows = 1e-10;  // m
  double largest_offset = 0;
  for (const Eigen::Vector3d& p : loaded.vertices) {
    const Eigen::Vector3d local = R.transpose() * (p - Eigen::Vector3d(0.3, 0.1, 0.7));
    largest_offset = std::max(largest_offset, std::abs(local.cwiseAbs().maxCoeff() - 0.05));
  }
  EXPECT_GT(largest_offset, kFloatRoundingShows);
  const ConvexHull hull = ComputeConvexHull(loaded.vertices, path);
  EXPECT_EQ(hull.faces.size(), 6u);
  EXPECT_EQ(hull.vertices.size(), 8u);
  ExpectValidHull(hull, loaded.vertices);
}

// The T-bar's hull is a prism over the hexagon (−a, b), (a, b), (a, c), (w, e), (−w, e),
// (−a, c) — bar top corners, bar bottom corners, stem tip corners; the inner corners (±w, c) lie
// inside since the chord from (a, c) to (w, e) passes below them. So 6 + 2 = 8 faces,
// 12 vertices, 18 edges.
TEST(ConvexHullTest, TBarHullIsAHexagonalPrism) {
  const TriangleMesh mesh = MakeTBarMesh();
  const ConvexHull hull = ComputeConvexHull(mesh.vertices, "T-bar");
  EXPECT_EQ(hull.faces.size(), 8u);
  EXPECT_EQ(hull.vertices.size(), 12u);
  EXPECT_EQ(CountEdges(hull), 18);
  ExpectValidHull(hull, mesh.vertices);
  int caps = 0;
  for (std::size_t i = 0; i < hull.faces.size(); ++i) {
    if (std::abs(hull.normals[i].z()) < 1 - kRoundOff) {
      EXPECT_NEAR(hull.normals[i].z(), 0.0, kUnitRoundOff);
      continue;
    }
    ++caps;
    EXPECT_EQ(hull.faces[i].size(), 6u);
    EXPECT_NEAR(hull.offsets[i], hull.normals[i].z() > 0 ? 0.05 : 0.0, kUnitRoundOff);
  }
  EXPECT_EQ(caps, 2);
}

// The desk's hull is its bounding box: grid nodes along its edges and faces are dropped.
TEST(ConvexHullTest, DeskHullIsItsBoundingBox) {
  const TriangleMesh mesh = MakeDeskMesh();
  const ConvexHull hull = ComputeConvexHull(mesh.vertices, "desk");
  EXPECT_EQ(hull.faces.size(), 6u);
  EXPECT_EQ(hull.vertices.size(), 8u);
  ExpectValidHull(hull, mesh.vertices);
}

// The 96-segment dumbbell's hull is the prism over its end discs' 96-gon: 98 faces.
TEST(ConvexHullTest, DumbbellHullIsAPrism) {
  const TriangleMesh mesh = MakeDumbbellMesh();
  const ConvexHull hull = ComputeConvexHull(mesh.vertices, "dumbbell");
  EXPECT_EQ(hull.faces.size(), 98u);
  EXPECT_EQ(hull.vertices.size(), 192u);
  ExpectValidHull(hull, mesh.vertices);
}

TEST(ConvexHullTest, RandomCloudContainsAllPointsAndUsesOnlyInputVertices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points(3000);
  for (Eigen::Vector3d& p : points) p = {uniform(rng), 0.5 * uniform(rng), 2.0 * uniform(rng)};
  const ConvexHull hull = ComputeConvexHull(points, "cloud");
  ExpectValidHull(hull, points);
  for (const Eigen::Vector3d& v : hull.vertices) {
    EXPECT_NE(std::find(points.begin(), points.end(), v), points.end());
  }
}

// Four points take CGAL's tetrahedron shortcut, whose indexed triangles face inwards: the hull
// still has outward normals and contains its points (with or without a duplicate point)
TEST(ConvexHullTest, FourPointsGiveAnOutwardTetrahedron) {
  std::vector<Eigen::Vector3d> points = {
      {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  for (int duplicates = 0; duplicates < 2; ++duplicates) {
    const ConvexHull hull = ComputeConvexHull(points, "tetrahedron");
    ASSERT_EQ(hull.faces.size(), 4u);
    EXPECT_EQ(hull.vertices.size(), 4u);
    ExpectValidHull(hull, points);
    // the slanted face's plane x + y + z = 1, outward
    int slanted = 0;
    for (std::size_t i = 0; i < hull.faces.size(); ++i) {
      if ((hull.normals[i] - Eigen::Vector3d::Ones().normalized()).norm() > kRoundOff) continue;
      ++slanted;
      EXPECT_NEAR(hull.offsets[i], 1 / std::sqrt(3.0), kRoundOff);
    }
    EXPECT_EQ(slanted, 1);
    points.push_back(points[1]);
  }
}

// Points on a sphere are all corners; the faces are triangles, except where four random points
// happen to be coplanar within the merge tolerance (a handful for 2000 points). Euler's formula
// gives Σ_f (corners_f − 2) = 2V − 4 for any polytope.
TEST(ConvexHullTest, SpherePointsAreAllCorners) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> points(2000);
  for (Eigen::Vector3d& p : points) {
    p = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }
  const ConvexHull hull = ComputeConvexHull(points, "sphere cloud");
  EXPECT_EQ(hull.vertices.size(), points.size());
  std::size_t triangles = 0;
  for (const auto& polygon : hull.faces) triangles += polygon.size() - 2;
  EXPECT_EQ(triangles, 2 * points.size() - 4);
  EXPECT_GE(hull.faces.size(), 2 * points.size() - 4 - 10);
  ExpectValidHull(hull, points);
}

// Issue 14: CGAL's convex_hull_3 shuffles its input with a process-wide random generator, so the
// same points gave the same hull with other vertex and face labels on every call — and a body's
// trajectory depended on what the process had computed before. The hull is now canonical.
TEST(ConvexHullTest, SamePointsGiveTheSameArraysOnEveryCall) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> points(700);
  for (Eigen::Vector3d& p : points) {
    p = Eigen::Vector3d(normal(rng), normal(rng), 0.3 * normal(rng)).normalized();
  }
  const ConvexHull first = ComputeConvexHull(points, "cloud");
  for (int call = 0; call < 3; ++call) {
    // other hulls in between advance CGAL's generator
    ComputeConvexHull(std::vector<Eigen::Vector3d>(points.begin(), points.begin() + 100 + call),
                      "other");
    const ConvexHull again = ComputeConvexHull(points, "cloud");
    EXPECT_EQ(again.vertices, first.vertices) << "call " << call;
    EXPECT_EQ(again.faces, first.faces) << "call " << call;
    EXPECT_EQ(again.normals, first.normals) << "call " << call;
    EXPECT_EQ(again.offsets, first.offsets) << "call " << call;
  }
  // and the labels follow the coordinates: vertices in lexicographic order
  EXPECT_TRUE(std::is_sorted(first.vertices.begin(), first.vertices.end(),
                             [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
                               return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
                             }));
}

// Issue 11: where input points are exactly coplanar, CGAL may triangulate a face in many ways
// (and keep a point on a face or edge as a vertex or not), depending on the input order and on
// heap addresses; every output must still be a function of the point set alone. An octahedron
// |x| + |y| + |z| ≤ 6 through all its lattice points (slanted faces of 28 points each, eighths
// of a metre: exact) and a box with grids on its faces, edges and inside, each hulled in
// several orders, must give bit-identical arrays, and the box's normals exact axes.
TEST(ConvexHullTest, ExactlyCoplanarPointsGiveTheSameHullInEveryOrder) {
  std::vector<Eigen::Vector3d> octahedron;
  for (int x = -6; x <= 6; ++x) {
    for (int y = -6; y <= 6; ++y) {
      for (int z = -6; z <= 6; ++z) {
        if (std::abs(x) + std::abs(y) + std::abs(z) <= 6) {
          octahedron.emplace_back(0.125 * x - 0.3, 0.125 * y + 0.1, 0.125 * z + 2.0);
        }
      }
    }
  }
  std::vector<Eigen::Vector3d> box;
  for (int i = 0; i <= 6; ++i) {
    for (int j = 0; j <= 4; ++j) {
      for (int k = 0; k <= 3; ++k) {
        box.emplace_back(0.1 + 0.3 * i / 6, -0.2 + 0.7 * j / 4, 0.05 + 0.11 * k / 3);
      }
    }
  }
  for (const auto* points : {&octahedron, &box}) {
    const ConvexHull first = ComputeConvexHull(*points, "lattice");
    ExpectValidHull(first, *points);
    ASSERT_EQ(first.faces.size(), points == &box ? 6u : 8u);
    EXPECT_EQ(first.vertices.size(), 6u + 2 * (points == &box));
    ExpectTheSameHullInEveryOrder(*points, first, 6, 3);
  }
  const ConvexHull hull = ComputeConvexHull(box, "box lattice");
  for (const Eigen::Vector3d& n : hull.normals) {
    EXPECT_EQ(n.cwiseAbs().maxCoeff(), 1.0) << n.transpose();
    EXPECT_EQ(n.cwiseAbs().sum(), 1.0) << n.transpose();
  }
}

// The hull depends on the extreme points alone: points added on its faces and edges and inside
// (which CGAL may keep as vertices of its triangles, depending on the order) change no bit.
TEST(ConvexHullTest, PointsOnFacesEdgesAndInsideChangeNoBit) {
  std::vector<Eigen::Vector3d> corners;
  std::vector<Eigen::Vector3d> lattice;
  for (int x = -4; x <= 4; ++x) {
    for (int y = -4; y <= 4; ++y) {
      for (int z = -4; z <= 4; ++z) {
        if (std::abs(x) + std::abs(y) + std::abs(z) > 4) continue;
        const Eigen::Vector3d p(0.25 * x + 1.0, 0.25 * y - 0.5, 0.25 * z + 0.75);
        lattice.push_back(p);
        // the octahedron's corners (±4, 0, 0), (0, ±4, 0), (0, 0, ±4)
        if (std::abs(x) == 4 || std::abs(y) == 4 || std::abs(z) == 4) corners.push_back(p);
      }
    }
  }
  ASSERT_EQ(corners.size(), 6u);
  const ConvexHull bare = ComputeConvexHull(corners, "octahedron corners");
  ExpectValidHull(bare, lattice);
  ExpectTheSameHullInEveryOrder(lattice, bare, 4, 9);
}

// Faces merged within the tolerance (a rotated cube rounded to float, with grids on its faces:
// no four points exactly coplanar but by chance) come out the same in every order too, their
// offsets searched over the hull.
TEST(ConvexHullTest, MergedFacesGiveTheSameHullInEveryOrder) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(-0.9, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  const std::vector<Eigen::Vector3d> points = FloatRoundedCubeGrid(R, Eigen::Vector3d::Zero(), 6);
  const ConvexHull first = ComputeConvexHull(points, "float cube");
  ASSERT_EQ(first.faces.size(), 6u);
  ExpectValidHull(first, points);
  ExpectTheSameHullInEveryOrder(points, first, 4, 4);
}

TEST(ConvexHullTest, DegenerateInputsThrowNamingTheSource) {
  const std::vector<Eigen::Vector3d> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THAT([&] { ComputeConvexHull(three, "meshes/tri.obj"); },
              ThrowsMessage<InputError>(HasSubstr("meshes/tri.obj: 3 points given")));

  std::vector<Eigen::Vector3d> collinear;
  for (int i = 0; i < 5; ++i) collinear.emplace_back(0.25 * i, 0.5 * i, -0.75 * i);
  EXPECT_THAT([&] { ComputeConvexHull(collinear, "line.stl"); },
              ThrowsMessage<InputError>(HasSubstr("line.stl: all 5 points are collinear")));

  std::vector<Eigen::Vector3d> flat;
  for (int i = 0; i < 8; ++i) flat.emplace_back(i % 3, i / 3, 0.25);
  EXPECT_THAT([&] { ComputeConvexHull(flat, "meshes/flat.obj"); },
              ThrowsMessage<InputError>(
                  HasSubstr("convex hull of meshes/flat.obj: all 8 points are coplanar "
                            "(volume 0); a hull needs a 3-D point set")));

  const std::vector<Eigen::Vector3d> same(6, Eigen::Vector3d(1, 2, 3));
  EXPECT_THAT([&] { ComputeConvexHull(same, "dots"); },
              ThrowsMessage<InputError>(HasSubstr("all 6 points coincide")));

  std::vector<Eigen::Vector3d> with_nan =
      BoxCorners(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  with_nan[5].y() = std::nan("");
  EXPECT_THAT([&] { ComputeConvexHull(with_nan, "bad.obj"); },
              ThrowsMessage<InputError>(HasSubstr("bad.obj: point 5 = (1, nan, 1) is not finite")));

  // 1e-9 m thick over a 1.4 m diagonal: below the 1e-6 relative merge tolerance
  std::vector<Eigen::Vector3d> sheet = flat;
  sheet.emplace_back(0.5, 0.5, 0.25 + 1e-9);
  EXPECT_THAT([&] { ComputeConvexHull(sheet, "sheet.obj"); },
              ThrowsMessage<InputError>(HasSubstr("sheet.obj: the points are flat within the "
                                                  "coplanar tolerance")));
}

TEST(ConvexHullTest, TranslateHullMovesOffsetsWithTheVertices) {
  const std::vector<Eigen::Vector3d> points = MakeTBarMesh().vertices;
  const Eigen::Vector3d shift(0.3, -1.2, 0.7);
  std::vector<Eigen::Vector3d> moved_points;
  for (const Eigen::Vector3d& p : points) moved_points.push_back(p + shift);
  const ConvexHull moved = TranslateHull(ComputeConvexHull(points), shift);
  ExpectValidHull(moved, moved_points);
  const ConvexHull direct = ComputeConvexHull(moved_points);
  ASSERT_EQ(moved.faces.size(), direct.faces.size());
  for (std::size_t i = 0; i < moved.faces.size(); ++i) {
    // each translated face appears in the direct hull with the same normal and offset
    bool found = false;
    for (std::size_t j = 0; j < direct.faces.size(); ++j) {
      if ((moved.normals[i] - direct.normals[j]).norm() < kRoundOff) {
        EXPECT_NEAR(moved.offsets[i], direct.offsets[j], kRoundOff);
        found = true;
      }
    }
    EXPECT_TRUE(found) << "face " << i;
  }
}

// The fanned hull is closed and outward: its signed volume is the box's, 0.6 × 0.4 × 0.2.
TEST(ConvexHullTest, TriangulateHullIsClosedAndOutward) {
  const ConvexHull hull =
      ComputeConvexHull(BoxCorners(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.3, 0.2, 0.1)));
  const TriangleMesh mesh = TriangulateHull(hull);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  double volume = 0;
  std::set<std::pair<int, int>> directed;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(directed.emplace(t[k], t[(k + 1) % 3]).second);
  }
  for (const auto& [a, b] : directed) EXPECT_EQ(directed.count({b, a}), 1u);
  EXPECT_NEAR(volume, 0.6 * 0.4 * 0.2, kRoundOff);
}

// Two UV spheres of 200 stacks × 400 slices, one inside the other's pole caps (the second
// stretched to 1.1 × 0.5 × 2): the exact hull has triangles whose area vector evaluates to
// exactly zero in doubles, which once stayed faces of their own without a normal (an internal
// error, exit code 4). Every face must come out with a unit normal and three corners or more, and
// the points inside.
TEST(ConvexHullTest, TrianglesOfZeroComputedAreaJoinANeighbouringFace) {
  constexpr int kStacks = 200;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i <= kStacks; ++i) {
    for (int j = 0; j < 2 * kStacks; ++j) {
      const double t = M_PI * i / kStacks, p = M_PI * j / kStacks;
      points.emplace_back(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      points.emplace_back(1.1 * std::sin(t) * std::cos(p), 0.5 * std::sin(t) * std::sin(p),
                          2 * std::cos(t));
    }
  }
  const ConvexHull hull = ComputeConvexHull(points, "two UV spheres");
  // m: the merge tolerance over this set's bounding-box diagonal (≈ 4.98), with round-off room
  const double tolerance = 2 * kCoplanarTolerance * 5.0;
  ASSERT_FALSE(hull.faces.empty());
  for (size_t f = 0; f < hull.faces.size(); ++f) {
    EXPECT_NEAR(hull.normals[f].norm(), 1, kRoundOff) << "face " << f;
    EXPECT_GE(hull.faces[f].size(), 3u) << "face " << f;
  }
  // every 97th point (97 is prime to the 400 points of a ring, so the sample walks all slices)
  // against every face: the whole set would take seconds
  for (size_t i = 0; i < points.size(); i += 97)
    for (size_t f = 0; f < hull.faces.size(); ++f)
      ASSERT_LE(hull.normals[f].dot(points[i]) - hull.offsets[f], tolerance) << "face " << f;
}

TEST(ConvexHull2DTest, SquareWithInteriorAndEdgePointsGivesItsCornersCounterClockwise) {
  const std::vector<Eigen::Vector2d> points = {{0, 0},     {1, 0}, {0.5, 0}, {1, 1},
                                               {0.3, 0.4}, {0, 1}, {0, 0.5}, {1, 1}};
  const std::vector<Eigen::Vector2d> hull = ComputeConvexHull2D(points);
  ASSERT_EQ(hull.size(), 4u);
  double twice_area = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const Eigen::Vector2d& a = hull[k];
    const Eigen::Vector2d& b = hull[(k + 1) % 4];
    twice_area += a.x() * b.y() - a.y() * b.x();
    const bool corner = (a.x() == 0 || a.x() == 1) && (a.y() == 0 || a.y() == 1);
    EXPECT_TRUE(corner) << a.transpose();
  }
  EXPECT_EQ(twice_area, 2.0);
}

TEST(ConvexHull2DTest, DegenerateInputsGiveOneOrTwoPoints) {
  EXPECT_TRUE(ComputeConvexHull2D({}).empty());
  const std::vector<Eigen::Vector2d> one = ComputeConvexHull2D({{2, 3}, {2, 3}, {2, 3}});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], Eigen::Vector2d(2, 3));
  const std::vector<Eigen::Vector2d> two =
      ComputeConvexHull2D({{1, 1}, {3, 2}, {-1, 0}, {2, 1.5}, {3, 2}});
  ASSERT_EQ(two.size(), 2u);
  const std::set<std::pair<double, double>> ends = {{two[0].x(), two[0].y()},
                                                    {two[1].x(), two[1].y()}};
  EXPECT_EQ(ends, (std::set<std::pair<double, double>>{{-1, 0}, {3, 2}}));
}

}  // namespace
}  // namespace ecpsim::geometry
