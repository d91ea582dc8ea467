#include "evaluation/mesh_generators.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>

#include <fmt/format.h>

#include "common/errors.h"
#include "evaluation/seeded_random.h"
#include "geometry/convex_hull.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using geometry::TriangleMesh;

constexpr double kPi = 3.14159265358979323846;
constexpr double kThinRatio = 100;  // plates and needles: the 100:1

using Grid = std::array<std::vector<double>, 3>;  // the grid lines along x, y and z

// the closed boundary of a union of cells of a rectilinear grid: a cell's face is a boundary
// face when the cell beyond it is empty. Grid points become shared vertices, so the surface is
// closed as long as filled cells meet along whole faces (none only along an edge or at a corner)
TriangleMesh CellUnionBoundary(const Grid& grid, const std::function<bool(int, int, int)>& filled) {
  const std::array<int, 3> cells = {static_cast<int>(grid[0].size()) - 1,
                                    static_cast<int>(grid[1].size()) - 1,
                                    static_cast<int>(grid[2].size()) - 1};
  const auto inside = [&](const std::array<int, 3>& c) {
    for (int a = 0; a < 3; ++a) {
      if (c[a] < 0 || c[a] >= cells[a]) return false;
    }
    return filled(c[0], c[1], c[2]);
  };
  TriangleMesh mesh;
  std::map<std::array<int, 3>, int> vertex_of_point;
  const auto vertex = [&](const std::array<int, 3>& point) {
    const auto [it, added] = vertex_of_point.emplace(point, static_cast<int>(mesh.vertices.size()));
    if (added) mesh.vertices.emplace_back(grid[0][point[0]], grid[1][point[1]], grid[2][point[2]]);
    return it->second;
  };
  std::array<int, 3> c;
  for (c[0] = 0; c[0] < cells[0]; ++c[0]) {
    for (c[1] = 0; c[1] < cells[1]; ++c[1]) {
      for (c[2] = 0; c[2] < cells[2]; ++c[2]) {
        if (!inside(c)) continue;
        for (int a = 0; a < 3; ++a) {
          for (int side : {-1, 1}) {
            std::array<int, 3> beyond = c;
            beyond[a] += side;
            if (inside(beyond)) continue;
            // the face's corners in the plane of axes b, c (e_b × e_c = e_a): counter-clockwise
            // seen from +e_a, reversed for the −e_a side
            const int b = (a + 1) % 3, d = (a + 2) % 3;
            const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            int corner[4];
            for (int k = 0; k < 4; ++k) {
              std::array<int, 3> point = c;
              point[a] += side > 0 ? 1 : 0;
              point[b] += uv[k][0];
              point[d] += uv[k][1];
              corner[side > 0 ? k : 3 - k] = vertex(point);
            }
            mesh.triangles.emplace_back(corner[0], corner[1], corner[2]);
            mesh.triangles.emplace_back(corner[0], corner[2], corner[3]);
          }
        }
      }
    }
  }
  return mesh;
}

std::vector<double> Lines(std::initializer_list<double> values) { return values; }

std::vector<double> EvenLines(double length, int cells) {
  std::vector<double> lines;
  for (int k = 0; k <= cells; ++k) lines.push_back(length * k / cells);
  return lines;
}

// a right prism along z over the convex counter-clockwise polygon, z ∈ [0, length]; each cap a
// fan around its centroid
TriangleMesh Prism(const std::vector<Vector2d>& polygon, double length) {
  const int n = static_cast<int>(polygon.size());
  TriangleMesh mesh;
  Vector2d centroid = Vector2d::Zero();
  for (const Vector2d& p : polygon) centroid += p / n;
  for (double z : {0.0, length}) {
    for (const Vector2d& p : polygon) mesh.vertices.emplace_back(p.x(), p.y(), z);
  }
  const int bottom = 2 * n, top = 2 * n + 1;
  mesh.vertices.emplace_back(centroid.x(), centroid.y(), 0.0);
  mesh.vertices.emplace_back(centroid.x(), centroid.y(), length);
  for (int k = 0; k < n; ++k) {
    const int next = (k + 1) % n;
    mesh.triangles.emplace_back(bottom, next, k);  // seen from below
    mesh.triangles.emplace_back(top, n + k, n + next);
    // side quad: edge direction × z points outward for a counter-clockwise polygon
    mesh.triangles.emplace_back(k, next, n + next);
    mesh.triangles.emplace_back(k, n + next, n + k);
  }
  return mesh;
}

// k points on the ellipse with semi-axes (a, b), at jittered even angles: a convex polygon,
// counter-clockwise
std::vector<Vector2d> EllipsePolygon(SeededRandom& random, int k, double a, double b) {
  const double start = random.Uniform(0, 2 * kPi);
  std::vector<Vector2d> polygon;
  for (int i = 0; i < k; ++i) {
    const double angle = start + 2 * kPi * (i + random.Uniform(-0.3, 0.3)) / k;
    polygon.emplace_back(a * std::cos(angle), b * std::sin(angle));
  }
  return polygon;
}

bool LexicographicLess(const Vector3d& p, const Vector3d& q) {
  return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
}

// the same mesh with its vertices in lexicographic order and its triangles sorted (each
// starting at its smallest index, winding kept): CGAL's hull lists vertices in an order that
// depends on the process's earlier allocations, and a mesh must be the same for the same seed
TriangleMesh Canonical(const TriangleMesh& mesh) {
  std::vector<int> order(mesh.vertices.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return LexicographicLess(mesh.vertices[a], mesh.vertices[b]); });
  TriangleMesh canonical;
  std::vector<int> index_of(mesh.vertices.size());
  for (size_t i = 0; i < order.size(); ++i) {
    index_of[order[i]] = static_cast<int>(i);
    canonical.vertices.push_back(mesh.vertices[order[i]]);
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    Eigen::Vector3i u(index_of[t[0]], index_of[t[1]], index_of[t[2]]);
    while (u[0] != u.minCoeff()) u = Eigen::Vector3i(u[1], u[2], u[0]);
    canonical.triangles.push_back(u);
  }
  std::sort(canonical.triangles.begin(), canonical.triangles.end(),
            [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
              return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
            });
  return canonical;
}

// the hull of the points, each (possibly merged, polygonal) face fanned from its
// lexicographically smallest corner: geometry::TriangulateHull fans from the first corner CGAL
// lists, which varies as the vertex order does
TriangleMesh ConvexPolytope(const std::vector<Vector3d>& points, const std::string& what) {
  const geometry::ConvexHull hull = geometry::ComputeConvexHull(points, what);
  TriangleMesh mesh;
  mesh.vertices = hull.vertices;
  for (std::vector<int> polygon : hull.faces) {
    std::rotate(polygon.begin(),
                std::min_element(polygon.begin(), polygon.end(),
                                 [&](int a, int b) {
                                   return LexicographicLess(hull.vertices[a], hull.vertices[b]);
                                 }),
                polygon.end());
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      mesh.triangles.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
    }
  }
  return Canonical(mesh);
}

void Append(TriangleMesh& mesh, const TriangleMesh& part, const Vector3d& offset) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (const Vector3d& v : part.vertices) mesh.vertices.push_back(v + offset);
  for (const Eigen::Vector3i& t : part.triangles) {
    mesh.triangles.push_back(t + Eigen::Vector3i::Constant(base));
  }
}

void BoundingBox(const TriangleMesh& mesh, Vector3d& lo, Vector3d& hi) {
  lo = Vector3d::Constant(INFINITY);
  hi = Vector3d::Constant(-INFINITY);
  for (const Vector3d& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
}

// moves the bounding box's centre to the origin and scales its diagonal to 1
void Normalize(TriangleMesh& mesh) {
  Vector3d lo, hi;
  BoundingBox(mesh, lo, hi);
  const Vector3d centre = (lo + hi) / 2;
  const double diagonal = (hi - lo).norm();
  ECPSIM_DEMAND(diagonal > 0);
  for (Vector3d& v : mesh.vertices) v = (v - centre) / diagonal;
}

GeneratedMesh Convex(SeededRandom& random) {
  const int n = static_cast<int>(std::lround(random.LogUniform(4, 2000)));
  const int variant = random.Integer(0, 3);
  const Vector3d radii(1, random.Uniform(0.2, 1), random.Uniform(0.2, 1));
  const bool surface = variant % 2 == 0, ellipsoid = variant >= 2;
  std::vector<Vector3d> points;
  for (int i = 0; i < n; ++i) {
    const Vector3d p = surface ? random.UnitVector() : random.InBall();
    points.push_back(ellipsoid ? Vector3d(p.cwiseProduct(radii)) : p);
  }
  const std::string description =
      fmt::format("{} points {} {}", n, surface ? "on" : "in",
                  ellipsoid ? fmt::format("an ellipsoid 1:{:.3g}:{:.3g}", radii.y(), radii.z())
                            : std::string("a sphere"));
  return {ConvexPolytope(points, description), description};
}

GeneratedMesh LShape(SeededRandom& random) {
  const double x = 1, y = random.Uniform(0.4, 1), z = random.Uniform(0.1, 0.6);
  const double arm_x = random.Uniform(0.15, 0.5) * x, arm_y = random.Uniform(0.15, 0.5) * y;
  // cells (0,0), (1,0), (0,1) of a 2 × 2 grid: the corner (1,1) is cut out
  const Grid grid = {Lines({0, arm_x, x}), Lines({0, arm_y, y}), Lines({0, z})};
  return {CellUnionBoundary(grid, [](int i, int j, int) { return i == 0 || j == 0; }),
          fmt::format("{:.3g} x {:.3g} x {:.3g} arms {:.3g} {:.3g}", x, y, z, arm_x, arm_y)};
}

GeneratedMesh TShape(SeededRandom& random) {
  const double x = 1, y = random.Uniform(0.4, 1.2), z = random.Uniform(0.1, 0.5);
  const double stem = random.Uniform(0.1, 0.5) * x, bar = random.Uniform(0.15, 0.5) * y;
  const double centre = random.Uniform(stem / 2 + 0.05, x - stem / 2 - 0.05);
  // the bar is the top row j = 1, the stem the middle cell of row 0
  const Grid grid = {Lines({0, centre - stem / 2, centre + stem / 2, x}), Lines({0, y - bar, y}),
                     Lines({0, z})};
  return {CellUnionBoundary(grid, [](int i, int j, int) { return j == 1 || i == 1; }),
          fmt::format("{:.3g} x {:.3g} x {:.3g} stem {:.3g} at {:.3g} bar {:.3g}", x, y, z, stem,
                      centre, bar)};
}

GeneratedMesh UShape(SeededRandom& random) {
  const double x = 1, y = random.Uniform(0.3, 1), z = random.Uniform(0.1, 0.6);
  const double left = random.Uniform(0.1, 0.4) * x, right = random.Uniform(0.1, 0.4) * x;
  const double base = random.Uniform(0.1, 0.6) * y;
  // the base is row j = 0, the uprights the outer cells of row 1
  const Grid grid = {Lines({0, left, x - right, x}), Lines({0, base, y}), Lines({0, z})};
  return {CellUnionBoundary(grid, [](int i, int j, int) { return j == 0 || i != 1; }),
          fmt::format("{:.3g} x {:.3g} x {:.3g} uprights {:.3g} {:.3g} base {:.3g}", x, y, z, left,
                      right, base)};
}

GeneratedMesh Torus(SeededRandom& random) {
  const double major = 1, minor = random.Uniform(0.1, 0.6);
  const int around = random.Integer(8, 96), tube = random.Integer(6, 32);
  TriangleMesh mesh;
  for (int i = 0; i < around; ++i) {
    const double theta = 2 * kPi * i / around;
    for (int j = 0; j < tube; ++j) {
      const double phi = 2 * kPi * j / tube;
      const double r = major + minor * std::cos(phi);
      mesh.vertices.emplace_back(r * std::cos(theta), r * std::sin(theta), minor * std::sin(phi));
    }
  }
  // (i, j) → (i+1, j) → (i+1, j+1): ∂θ × ∂φ points out of the tube
  const auto index = [&](int i, int j) { return (i % around) * tube + j % tube; };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      mesh.triangles.emplace_back(index(i, j), index(i + 1, j), index(i + 1, j + 1));
      mesh.triangles.emplace_back(index(i, j), index(i + 1, j + 1), index(i, j + 1));
    }
  }
  return {mesh, fmt::format("radii 1 {:.3g} segments {} x {}", minor, around, tube)};
}

GeneratedMesh Plate(SeededRandom& random) {
  const int k = random.Integer(3, 32);
  const double aspect = random.Uniform(0.3, 1);
  const std::vector<Vector2d> outline = EllipsePolygon(random, k, 0.5, 0.5 * aspect);
  return {Prism(outline, 1 / kThinRatio),
          fmt::format("{}-gon in an ellipse 1 x {:.3g} thickness 1/{:g}", k, aspect, kThinRatio)};
}

GeneratedMesh Needle(SeededRandom& random) {
  const int k = random.Integer(3, 16);
  const double aspect = random.Uniform(0.5, 1);
  const double radius = 0.5 / kThinRatio;
  const std::vector<Vector2d> section = EllipsePolygon(random, k, radius, radius * aspect);
  return {Prism(section, 1), fmt::format("{}-gon section 1/{:g} x {:.3g}/{:g} length 1", k,
                                         kThinRatio, aspect, kThinRatio)};
}

GeneratedMesh Coplanar(SeededRandom& random) {
  const Vector3d size(1, random.Uniform(0.3, 1), random.Uniform(0.3, 1));
  const int cells = random.Integer(4, 24);
  const double jitter = random.LogUniform(1e-9, 1e-5);
  const Grid grid = {EvenLines(size.x(), cells), EvenLines(size.y(), cells),
                     EvenLines(size.z(), cells)};
  TriangleMesh mesh = CellUnionBoundary(grid, [](int, int, int) { return true; });
  Normalize(mesh);
  // every vertex moved by `jitter` × the diagonal in a random direction: the faces' quads are
  // no longer exactly coplanar
  for (Vector3d& v : mesh.vertices) v += jitter * random.UnitVector();
  return {mesh, fmt::format("box 1 x {:.3g} x {:.3g} {} cells per edge jitter {:.2g}", size.y(),
                            size.z(), cells, jitter)};
}

GeneratedMesh Terrain(SeededRandom& random) {
  const double y = random.Uniform(0.5, 1), z = random.Uniform(0.05, 0.3);
  const int nx = random.Integer(8, 48), ny = random.Integer(8, 48);
  const double relief = random.LogUniform(1e-6, 1e-2);
  const Grid grid = {EvenLines(1, nx), EvenLines(y, ny), Lines({0, z})};
  TriangleMesh mesh = CellUnionBoundary(grid, [](int, int, int) { return true; });
  // the top's heights: three random waves plus per-vertex noise, all within ±relief
  struct Wave {
    Vector2d k;
    double phase;
  };
  std::vector<Wave> waves;
  for (int w = 0; w < 3; ++w) {
    const double angle = random.Uniform(0, 2 * kPi), number = random.Uniform(1, 8) * 2 * kPi;
    const double phase = random.Uniform(0, 2 * kPi);
    waves.push_back({number * Vector2d(std::cos(angle), std::sin(angle)), phase});
  }
  for (Vector3d& v : mesh.vertices) {
    if (v.z() != z) continue;
    double height = 0;
    for (const Wave& w : waves) height += std::sin(w.k.dot(v.head<2>()) + w.phase) / 4;
    v.z() += relief * (height + random.Uniform(-0.25, 0.25));
  }
  return {mesh,
          fmt::format("slab 1 x {:.3g} x {:.3g} top {} x {} relief {:.2g}", y, z, nx, ny, relief)};
}

GeneratedMesh Disconnected(SeededRandom& random) {
  const int parts = random.Integer(2, 3);
  TriangleMesh mesh;
  std::string description = fmt::format("{} parts:", parts);
  double cursor = 0;
  for (int p = 0; p < parts; ++p) {
    TriangleMesh part;
    const double scale = random.Uniform(0.3, 1);
    if (random.Integer(0, 1) == 0) {
      const Vector3d size =
          scale * Vector3d(random.Uniform(0.3, 1), random.Uniform(0.3, 1), random.Uniform(0.3, 1));
      part = CellUnionBoundary({Lines({0, size.x()}), Lines({0, size.y()}), Lines({0, size.z()})},
                               [](int, int, int) { return true; });
      description += fmt::format(" box {:.3g} x {:.3g} x {:.3g}", size.x(), size.y(), size.z());
    } else {
      const int n = random.Integer(4, 60);
      std::vector<Vector3d> points;
      for (int i = 0; i < n; ++i) points.push_back(scale / 2 * random.InBall());
      part = ConvexPolytope(points, "disconnected part");
      description += fmt::format(" hull of {} points", n);
    }
    // parts in a row along x with gaps, each shifted across at random
    Vector3d lo, hi;
    BoundingBox(part, lo, hi);
    const Vector3d offset(cursor - lo.x(), random.Uniform(-0.3, 0.3), random.Uniform(-0.3, 0.3));
    Append(mesh, part, offset);
    const double gap = random.Uniform(0.05, 0.5);
    cursor += hi.x() - lo.x() + gap;
    if (p + 1 < parts) description += fmt::format(" gap {:.3g};", gap);
  }
  return {mesh, description};
}

}  // namespace

const char* MeshKindName(MeshKind kind) {
  switch (kind) {
    case MeshKind::kConvex:
      return "convex";
    case MeshKind::kLShape:
      return "l_shape";
    case MeshKind::kTShape:
      return "t_shape";
    case MeshKind::kUShape:
      return "u_shape";
    case MeshKind::kTorus:
      return "torus";
    case MeshKind::kPlate:
      return "plate";
    case MeshKind::kNeedle:
      return "needle";
    case MeshKind::kCoplanar:
      return "coplanar";
    case MeshKind::kTerrain:
      return "terrain";
    case MeshKind::kDisconnected:
      return "disconnected";
  }
  return "unknown";
}

std::vector<MeshKind> AllMeshKinds() {
  std::vector<MeshKind> kinds;
  for (int k = 0; k < kMeshKindCount; ++k) kinds.push_back(static_cast<MeshKind>(k));
  return kinds;
}

GeneratedMesh GenerateMesh(MeshKind kind, std::uint64_t seed) {
  SeededRandom random(seed, static_cast<std::uint64_t>(kind));
  GeneratedMesh generated;
  switch (kind) {
    case MeshKind::kConvex:
      generated = Convex(random);
      break;
    case MeshKind::kLShape:
      generated = LShape(random);
      break;
    case MeshKind::kTShape:
      generated = TShape(random);
      break;
    case MeshKind::kUShape:
      generated = UShape(random);
      break;
    case MeshKind::kTorus:
      generated = Torus(random);
      break;
    case MeshKind::kPlate:
      generated = Plate(random);
      break;
    case MeshKind::kNeedle:
      generated = Needle(random);
      break;
    case MeshKind::kCoplanar:
      generated = Coplanar(random);
      break;
    case MeshKind::kTerrain:
      generated = Terrain(random);
      break;
    case MeshKind::kDisconnected:
      generated = Disconnected(random);
      break;
    default:
      ECPSIM_DEMAND(false && "unknown mesh kind");
  }
  Normalize(generated.mesh);
  return generated;
}

}  // namespace ecpsim::evaluation
