// DecomposeSolid: a solid mesh's convex parts, merged where their union is convex or, within a
// tolerance, where their hull stays that close to the solid, their seams moved inside a part.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "geometry/convex_decomposition.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_bounds.h"
#include "geometry/mesh_io.h"
#include "geometry/part_seams.h"
#include "geometry/weld_vertices.h"

namespace ecpsim::geometry {
namespace {

// the closed surface of a union of axis-aligned cells of edge `cell` (a voxel solid), outward
TriangleMesh Cells(const std::vector<Eigen::Vector3i>& cells, double cell) {
  TriangleMesh mesh;
  const auto filled = [&](const Eigen::Vector3i& c) {
    for (const Eigen::Vector3i& d : cells)
      if (d == c) return true;
    return false;
  };
  for (const Eigen::Vector3i& c : cells) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int side : {-1, 1}) {
        Eigen::Vector3i next = c;
        next[axis] += side;
        if (filled(next)) continue;
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        Eigen::Vector3d base = c.cast<double>() * cell;
        if (side > 0) base[axis] += cell;
        Eigen::Vector3d corners[4];
        for (int k = 0; k < 4; ++k) {
          corners[k] = base;
          corners[k][u] += (k == 1 || k == 2) ? cell : 0;
          corners[k][w] += (k >= 2) ? cell : 0;
        }
        const int first = static_cast<int>(mesh.vertices.size());
        for (const Eigen::Vector3d& p : corners) mesh.vertices.push_back(p);
        if (side > 0) {
          mesh.triangles.emplace_back(first, first + 1, first + 2);
          mesh.triangles.emplace_back(first, first + 2, first + 3);
        } else {
          mesh.triangles.emplace_back(first, first + 2, first + 1);
          mesh.triangles.emplace_back(first, first + 3, first + 2);
        }
      }
    }
  }
  return WeldVertices(mesh, 1e-9 * cell);
}

// a cup of 4 × 4 × 3 cells: a floor of 4 × 4 and walls one cell thick, two cells high
std::vector<Eigen::Vector3i> CupCells() {
  std::vector<Eigen::Vector3i> cells;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 3; ++z)
        if (z == 0 || x == 0 || x == 3 || y == 0 || y == 3) cells.emplace_back(x, y, z);
  return cells;
}

TEST(ConvexDecompositionTest, ACupSplitsIntoConvexPartsWithoutSeamsOnItsSurface) {
  const double cell = 0.01;
  const TriangleMesh cup = Cells(CupCells(), cell);
  const std::vector<ConvexHull> parts = DecomposeSolid(cup, "cup", 64, 0);
  // at least a floor and four walls, and the cells merged where they can be
  EXPECT_GE(parts.size(), 5u);
  EXPECT_LE(parts.size(), 9u);
  // the parts fill the cup: their volumes sum to its volume plus the overlaps the seams' growth
  // adds (each at most kSeamOverlapRel × the diagonal over a seam of at most 4 × 1 cells)
  const double volume = ComputeMassProperties(cup, 1, "cup").volume;
  double sum = 0;
  for (const ConvexHull& part : parts) sum += HullVolume(part);
  const double diagonal = std::sqrt(4 * 4 + 4 * 4 + 3 * 3) * cell;
  EXPECT_GE(sum, volume * (1 - 1e-12));
  EXPECT_LE(sum, volume + parts.size() * 2 * (kSeamOverlapRel * diagonal) * 4 * cell * cell);
  // no two parts meet face to face any more
  for (size_t i = 0; i < parts.size(); ++i)
    for (size_t j = i + 1; j < parts.size(); ++j)
      EXPECT_FALSE(FindSeam(parts[i], parts[j], 1e-9)) << i << ", " << j;
}

TEST(ConvexDecompositionTest, ABoxOfCellsIsOnePart) {
  std::vector<Eigen::Vector3i> cells;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 2; ++y) cells.emplace_back(x, y, 0);
  const std::vector<ConvexHull> parts = DecomposeSolid(Cells(cells, 0.1), "box", 64, 0);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_NEAR(HullVolume(parts[0]), 0.3 * 0.2 * 0.1, 1e-15);
}

TEST(ConvexDecompositionTest, MorePartsThanAllowedIsAnError) {
  try {
    DecomposeSolid(Cells(CupCells(), 0.01), "cup.obj", 2, 0);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("convex decomposition of cup.obj:"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("more than 2"), std::string::npos) << e.what();
  }
}

TEST(ConvexDecompositionTest, AnOpenSurfaceIsRefused) {
  TriangleMesh open = Cells({{0, 0, 0}}, 0.1);
  open.triangles.pop_back();
  EXPECT_THROW(DecomposeSolid(open, "open.obj", 64, 0), InputError);
}

TEST(ConvexDecompositionTest, ASurfaceThatMeetsItselfIsRefused) {
  // a cup's surface and a cube's in one mesh, each closed, the cube through the cup's wall and,
  // in the middle, where the check splits the triangles between its two threads, through its
  // floor (the cup has reflex edges, which CGAL's clip would cut, and on such a surface may
  // crash)
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(0.035, 0.015, 0.015), Eigen::Vector3d(0.015, 0.015, -0.005)}) {
    TriangleMesh two = Cells(CupCells(), 0.01);
    const TriangleMesh other = Cells({{0, 0, 0}}, 0.01);
    const int first = static_cast<int>(two.vertices.size());
    for (const Eigen::Vector3d& v : other.vertices) two.vertices.push_back(v + offset);
    for (const Eigen::Vector3i& t : other.triangles) two.triangles.push_back(t.array() + first);
    try {
      DecomposeSolid(two, "two.obj", 64, 0);
      FAIL() << "expected an InputError for the cube at " << offset.transpose();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("convex decomposition of two.obj: the mesh "
                                           "intersects itself"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(ConvexDecompositionTest, ATriangleWithoutAreaIsRefused) {
  // a cube whose top's corner 2 moved onto the line of corners 0 and 1 of a top triangle
  TriangleMesh sliver = Cells({{0, 0, 0}}, 0.1);
  int top = -1;
  for (size_t t = 0; t < sliver.triangles.size() && top < 0; ++t) {
    const Eigen::Vector3i& c = sliver.triangles[t];
    if (sliver.vertices[c[0]].z() > 0.05 && sliver.vertices[c[1]].z() > 0.05 &&
        sliver.vertices[c[2]].z() > 0.05) {
      top = static_cast<int>(t);
    }
  }
  ASSERT_GE(top, 0);
  const Eigen::Vector3i c = sliver.triangles[top];
  sliver.vertices.push_back((sliver.vertices[c[0]] + sliver.vertices[c[1]]) / 2);
  sliver.triangles[top][2] = static_cast<int>(sliver.vertices.size()) - 1;
  try {
    DecomposeSolid(sliver, "sliver.obj", 64, 0);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fmt::format("convex decomposition of sliver.obj: "
                                                     "triangle {} has no area",
                                                     top)),
              std::string::npos)
        << e.what();
  }
}

TEST(ConvexDecompositionTest, MorePartsThanAllowedSaysToRaiseTheTolerance) {
  try {
    DecomposeSolid(Cells(CupCells(), 0.01), "cup.obj", 2, 1e-3);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("raise the tolerance"), std::string::npos) << e.what();
  }
}

TEST(ConvexDecompositionTest, AToleranceOutsideZeroToOneIsAnError) {
  const TriangleMesh box = Cells({{0, 0, 0}}, 0.1);
  for (double tolerance : {-1e-3, 1.0, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    try {
      DecomposeSolid(box, "box.obj", 64, tolerance);
      FAIL() << "expected an InputError for " << tolerance;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("convex decomposition of box.obj: tolerance = "),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(">= 0 and < 1"), std::string::npos) << e.what();
    }
  }
}

// a block L × D × H (x, y, z) with a V-groove of depth `groove` across its top, along y: its
// profile in x–z extruded over y ∈ [0, D]
TriangleMesh GroovedBlock(double l, double d, double h, double groove) {
  const std::vector<Eigen::Vector2d> profile = {
      {0, 0}, {l, 0}, {l, h}, {l / 2, h - groove}, {0, h}};  // counter-clockwise seen from −y
  const int n = static_cast<int>(profile.size());
  TriangleMesh mesh;
  for (double y : {0.0, d})
    for (const Eigen::Vector2d& p : profile) mesh.vertices.emplace_back(p.x(), y, p.y());
  for (int k = 0; k < n; ++k) {
    const int next = (k + 1) % n;
    mesh.triangles.emplace_back(k, n + k, n + next);
    mesh.triangles.emplace_back(k, n + next, next);
  }
  // the ends fanned from the groove's bottom, which sees the whole profile
  for (int k : {4, 0, 1}) {
    const int next = (k + 1) % n;
    mesh.triangles.emplace_back(3, k, next);
    mesh.triangles.emplace_back(n + 3, n + next, n + k);
  }
  return mesh;
}

TEST(ConvexDecompositionTest, AGrooveMergesWhereTheToleranceCoversItsDepth) {
  const double l = 0.1, d = 0.05, h = 0.05, groove = 0.002;
  const TriangleMesh block = GroovedBlock(l, d, h, groove);
  ASSERT_NEAR(ComputeMassProperties(block, 1, "block").volume, l * d * h - l * groove / 2 * d,
              1e-15);
  const double diagonal = std::sqrt(l * l + d * d + h * h);
  // the hull of the two sides is the whole block; its point farthest from the solid is the
  // groove's top middle, at its distance from a wall of the groove
  const double reach = groove * (l / 2) / std::hypot(l / 2, groove);
  // CGAL's exact pieces: a side either side of the groove's bottom, one split again
  const std::size_t exact = DecomposeSolid(block, "block", 64, 0).size();
  EXPECT_GE(exact, 2u);
  EXPECT_EQ(DecomposeSolid(block, "block", 64, 0.9 * reach / diagonal).size(), 2u);
  const std::vector<ConvexHull> merged = DecomposeSolid(block, "block", 64, 2 * reach / diagonal);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_NEAR(HullVolume(merged[0]), l * d * h, 1e-15);
}

// the dumbbell of scenes/meshes/dumbbell.obj: discs of radius 0.1 m over |x| ∈ [0.09, 0.15] m
// and a bar of radius 0.05 m, 96 segments round
constexpr double kDiscRadius = 0.1, kBarRadius = 0.05, kBarHalf = 0.09, kHalfLength = 0.15;
constexpr int kSegments = 96;

// m: the distance from p to the round dumbbell the mesh is inscribed in (the union of three
// cylinders, closed form); the mesh's solid lies inside it, so its distance is at least this
double DistanceToRoundDumbbell(const Eigen::Vector3d& p) {
  const double r = std::hypot(p.y(), p.z());
  const auto cylinder = [&](double centre, double half, double radius) {
    return std::hypot(std::max(std::abs(p.x() - centre) - half, 0.0), std::max(r - radius, 0.0));
  };
  const double disc_half = (kHalfLength - kBarHalf) / 2;
  return std::min({cylinder(-kBarHalf - disc_half, disc_half, kDiscRadius),
                   cylinder(kBarHalf + disc_half, disc_half, kDiscRadius),
                   cylinder(0, kBarHalf, kBarRadius)});
}

bool InPart(const ConvexHull& part, const Eigen::Vector3d& p, double slack) {
  for (size_t f = 0; f < part.normals.size(); ++f)
    if (part.normals[f].dot(p) > part.offsets[f] + slack) return false;
  return true;
}

// every point well inside the dumbbell's mesh (inside the polygons inscribed in the circles, by
// 0.1 mm) lies in a part, and no point of a part lies farther than `bound` from its solid: each
// part's corners and a 1 mm grid through it, against the round dumbbell (an independent,
// closed-form lower bound of the distance to the mesh's solid)
void ExpectPartsHoldTheDumbbell(const std::vector<ConvexHull>& parts, double bound) {
  const double inscribed = std::cos(M_PI / kSegments);
  const double margin = 1e-4, step = 0.005;
  int inside = 0;
  for (double x = -kHalfLength; x <= kHalfLength; x += step) {
    for (double y = -kDiscRadius; y <= kDiscRadius; y += step) {
      for (double z = -kDiscRadius; z <= kDiscRadius; z += step) {
        const Eigen::Vector3d p(x, y, z);
        const double radius = std::abs(x) > kBarHalf + margin ? kDiscRadius : kBarRadius;
        if (std::abs(x) > kHalfLength - margin || std::abs(std::abs(x) - kBarHalf) < margin ||
            std::hypot(y, z) > radius * inscribed - margin) {
          continue;
        }
        ++inside;
        EXPECT_TRUE(std::any_of(parts.begin(), parts.end(), [&](const ConvexHull& part) {
          return InPart(part, p, 1e-12);
        })) << p.transpose();
      }
    }
  }
  EXPECT_GT(inside, 10000);
  const double fine = 0.001;
  for (size_t i = 0; i < parts.size(); ++i) {
    double farthest = 0;
    for (const Eigen::Vector3d& v : parts[i].vertices)
      farthest = std::max(farthest, DistanceToRoundDumbbell(v));
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& v : parts[i].vertices) box.extend(v);
    for (double x = box.min().x(); x <= box.max().x(); x += fine)
      for (double y = box.min().y(); y <= box.max().y(); y += fine)
        for (double z = box.min().z(); z <= box.max().z(); z += fine)
          if (InPart(parts[i], {x, y, z}, 0))
            farthest = std::max(farthest, DistanceToRoundDumbbell({x, y, z}));
    EXPECT_LE(farthest, bound) << "part " << i;
  }
}

// m: round-off of coordinates of 0.1 m (the rounded corners of the cuts)
constexpr double kCoordinateRoundOff = 1e-15;
// relative: a hull's volume sums some 3,000 fanned triangles' products, each rounded
constexpr double kVolumeRoundOff = 1e-11;

TEST(ConvexDecompositionTest, ADumbbellIsExactlyItsDiscsAndItsBar) {
  const TriangleMesh dumbbell =
      LoadMesh(std::string(ECPSIM_SOURCE_DIR) + "/scenes/meshes/dumbbell.obj");
  // one cut at each annulus where a disc meets the bar frees all its reflex edges at once
  const std::vector<ConvexHull> parts = DecomposeSolid(dumbbell, "dumbbell.obj", 64, 0);
  ASSERT_EQ(parts.size(), 3u);
  // a part's face planes lie within the hull's face-merging tolerance of its corners
  ExpectPartsHoldTheDumbbell(parts,
                             kCoplanarTolerance * ComputeMeshBounds(dumbbell.vertices).diagonal);
  // the parts' volumes: the solid's, and the bar's two ends grown into the discs (each the
  // inscribed 96-gon of the bar's circle, kSeamOverlapRel of the diagonal deep)
  const double volume = ComputeMassProperties(dumbbell, 1, "dumbbell").volume;
  const double end = kSegments / 2.0 * kBarRadius * kBarRadius * std::sin(2 * M_PI / kSegments);
  const double depth = kSeamOverlapRel * ComputeMeshBounds(dumbbell.vertices).diagonal;
  double sum = 0;
  for (const ConvexHull& part : parts) sum += HullVolume(part);
  EXPECT_NEAR(sum, volume + 2 * end * depth, kVolumeRoundOff * volume);
}

TEST(ConvexDecompositionTest, ADumbbellWithinAToleranceIsTheSameThreeParts) {
  const TriangleMesh dumbbell =
      LoadMesh(std::string(ECPSIM_SOURCE_DIR) + "/scenes/meshes/dumbbell.obj");
  // no two of them merge within 1e-3 of the diagonal: the hull of a disc and the bar reaches
  // half the discs' overhang (25 mm) out
  const double tolerance = 1e-3;
  const std::vector<ConvexHull> parts = DecomposeSolid(dumbbell, "dumbbell.obj", 64, tolerance);
  EXPECT_EQ(parts.size(), 3u);
  ExpectPartsHoldTheDumbbell(parts, tolerance * ComputeMeshBounds(dumbbell.vertices).diagonal);
}

// a thick-walled tube (a mug's wall): the ring between circles of radius `inner` and `outer`
// (inscribed `segments`-gons) over z in [0, height]
TriangleMesh Tube(double inner, double outer, double height, int segments) {
  TriangleMesh mesh;
  for (double z : {0.0, height}) {
    for (double r : {inner, outer}) {
      for (int k = 0; k < segments; ++k) {
        const double angle = 2 * M_PI * k / segments;
        mesh.vertices.emplace_back(r * std::cos(angle), r * std::sin(angle), z);
      }
    }
  }
  // ring (z index, radius index) starts at (2 z + r) × segments
  const auto at = [&](int z, int r, int k) { return (2 * z + r) * segments + k % segments; };
  const auto quad = [&](int a, int b, int c, int d) {  // counter-clockwise seen from outside
    mesh.triangles.emplace_back(a, b, c);
    mesh.triangles.emplace_back(a, c, d);
  };
  for (int k = 0; k < segments; ++k) {
    quad(at(0, 1, k), at(0, 1, k + 1), at(1, 1, k + 1), at(1, 1, k));  // outer wall
    quad(at(0, 0, k + 1), at(0, 0, k), at(1, 0, k), at(1, 0, k + 1));  // inner wall
    quad(at(1, 0, k), at(1, 1, k), at(1, 1, k + 1), at(1, 0, k + 1));  // top
    quad(at(0, 0, k), at(0, 0, k + 1), at(0, 1, k + 1), at(0, 1, k));  // bottom
  }
  return mesh;
}

TEST(ConvexDecompositionTest, ATubesWallWithinAToleranceIsAFewPartsThatHoldIt) {
  const double inner = 0.04, outer = 0.05, height = 0.06;
  const int segments = 48;
  const TriangleMesh tube = Tube(inner, outer, height, segments);
  ASSERT_NEAR(
      ComputeMassProperties(tube, 1, "tube").volume,
      segments / 2.0 * std::sin(2 * M_PI / segments) * (outer * outer - inner * inner) * height,
      1e-15);
  // exactly, each facet of the inner wall bounds a part
  EXPECT_THROW(DecomposeSolid(tube, "tube.obj", segments - 1, 0), InputError);
  const double tolerance = 1e-2;
  const double bound = tolerance * ComputeMeshBounds(tube.vertices).diagonal;
  const std::vector<ConvexHull> parts = DecomposeSolid(tube, "tube.obj", 64, tolerance);
  // a part spanning φ of the wall bulges inner (1 − cos φ/2) into the hole: for two pieces
  // (15°) 0.34 mm, well within the bound's 2/3 that ReachesWithin surely accepts (1.0 mm), so
  // at least the pairs merge (measured: 24 parts, the pairs)
  EXPECT_LE(parts.size(), static_cast<std::size_t>(segments / 2));
  // the wall's points, by 0.1 mm inside it, each in a part
  const double apothem = inner * std::cos(M_PI / segments);
  const double rim = outer * std::cos(M_PI / segments);
  for (int k = 0; k < 720; ++k) {
    const double angle = 2 * M_PI * k / 720;
    for (double r = apothem + 1e-4; r <= rim - 1e-4; r += 0.002) {
      for (double z = 1e-4; z <= height - 1e-4; z += 0.01) {
        const Eigen::Vector3d p(r * std::cos(angle), r * std::sin(angle), z);
        EXPECT_TRUE(std::any_of(parts.begin(), parts.end(), [&](const ConvexHull& part) {
          return InPart(part, p, 1e-12);
        })) << p.transpose();
      }
    }
  }
  // no part reaches into the hole (the inner 96-gon, convex: the distance from a point in it to
  // the wall is its least distance to an edge's line) farther than the bound, nor out of the
  // outer 96-gon, above or below
  const auto into_hole = [&](const Eigen::Vector3d& p) {
    double distance = INFINITY;
    for (int k = 0; k < segments; ++k) {
      const double angle = 2 * M_PI * (k + 0.5) / segments;
      distance = std::min(distance, apothem - (p.x() * std::cos(angle) + p.y() * std::sin(angle)));
    }
    return std::max(distance, 0.0);
  };
  for (const ConvexHull& part : parts) {
    for (const Eigen::Vector3d& v : part.vertices) {
      EXPECT_LE(into_hole(v), bound) << v.transpose();
      EXPECT_LE(std::hypot(v.x(), v.y()), outer + kCoordinateRoundOff) << v.transpose();
      EXPECT_GE(v.z(), -kCoordinateRoundOff);
      EXPECT_LE(v.z(), height + kCoordinateRoundOff);
    }
  }
}

}  // namespace
}  // namespace ecpsim::geometry
