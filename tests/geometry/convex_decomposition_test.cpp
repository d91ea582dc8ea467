// DecomposeSolid: a solid mesh's convex parts, merged where their union is convex or, within a
// tolerance, where their hull stays that close to the solid, their seams moved inside a part.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

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

TEST(ConvexDecompositionTest, ADumbbellWithinAToleranceIsAFewPartsThatHoldIt) {
  const TriangleMesh dumbbell =
      LoadMesh(std::string(ECPSIM_SOURCE_DIR) + "/scenes/meshes/dumbbell.obj");
  // its exact pieces are one per facet strip, too many
  EXPECT_THROW(DecomposeSolid(dumbbell, "dumbbell.obj", 64, 0), InputError);
  const double tolerance = 1e-3;
  const std::vector<ConvexHull> parts = DecomposeSolid(dumbbell, "dumbbell.obj", 64, tolerance);
  EXPECT_LE(parts.size(), 5u);
  const double bound = tolerance * ComputeMeshBounds(dumbbell.vertices).diagonal;
  // every point well inside the mesh (inside the polygons inscribed in the circles, by 0.1 mm)
  // is in a part
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
  // no point of a part farther than the bound from the solid: each part's corners and a 1 mm
  // grid through it, against the round dumbbell (an independent, closed-form lower bound of the
  // distance to the mesh's solid)
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

}  // namespace
}  // namespace ecpsim::geometry
