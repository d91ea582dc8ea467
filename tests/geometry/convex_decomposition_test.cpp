// DecomposeSolid: a solid mesh's convex parts, merged where their union is convex, their seams
// moved inside a part.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/errors.h"
#include "geometry/convex_decomposition.h"
#include "geometry/mass_properties.h"
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
  const std::vector<ConvexHull> parts = DecomposeSolid(cup, "cup", 64);
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
  const std::vector<ConvexHull> parts = DecomposeSolid(Cells(cells, 0.1), "box", 64);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_NEAR(HullVolume(parts[0]), 0.3 * 0.2 * 0.1, 1e-15);
}

TEST(ConvexDecompositionTest, MorePartsThanAllowedIsAnError) {
  try {
    DecomposeSolid(Cells(CupCells(), 0.01), "cup.obj", 2);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("convex decomposition of cup.obj:"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("more than 2"), std::string::npos) << e.what();
  }
}

TEST(ConvexDecompositionTest, AnOpenSurfaceIsRefused) {
  TriangleMesh open = Cells({{0, 0, 0}}, 0.1);
  open.triangles.pop_back();
  EXPECT_THROW(DecomposeSolid(open, "open.obj", 64), InputError);
}

}  // namespace
}  // namespace ecpsim::geometry
