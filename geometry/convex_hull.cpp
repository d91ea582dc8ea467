#include "geometry/convex_hull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <fmt/format.h>
#include <Eigen/Geometry>
#include <boost/sort/spreadsort/float_sort.hpp>

#include "common/cpu_clock.h"
#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Point2 = Kernel::Point_2;
// convex_hull_3 writes its triangles straight into arrays (the indexed triangle set of its
// documented convex_hull_3(first, last, vertices, faces) overload, which is much cheaper than
// building a Surface_mesh), with the traits it picks for a Surface_mesh: the exact, statically
// filtered plane-side test (the documented overload that takes traits does not compile in
// CGAL 5.5, its point type is not deducible)
using HullTriangles =
    CGAL::Convex_hull_3::internal::Indexed_triangle_set<std::vector<Point3>,
                                                        std::vector<std::array<int, 3>>>;
using HullTraits = CGAL::Convex_hull_traits_3<Kernel, HullTriangles, CGAL::Tag_true>;

// the flatness test looks at the normals of this many of the largest hull triangles
constexpr int kFlatnessProbes = 16;

Eigen::Vector3d ToEigen(const Point3& p) { return {p.x(), p.y(), p.z()}; }

// rejects point sets that cannot bound a volume, with exact predicates, before CGAL sees them
void CheckFullDimensional(const std::vector<Point3>& points, const std::string& source) {
  const std::size_t n = points.size();
  std::size_t second = 1;
  while (second < n && points[second] == points[0]) ++second;
  if (second == n) {
    throw InputError(fmt::format(
        "convex hull of {}: all {} points coincide (volume 0); a hull needs a 3-D point set",
        source, n));
  }
  std::size_t third = second + 1;
  while (third < n && CGAL::collinear(points[0], points[second], points[third])) ++third;
  if (third == n) {
    throw InputError(fmt::format(
        "convex hull of {}: all {} points are collinear (volume 0); a hull needs a 3-D point set",
        source, n));
  }
  std::size_t fourth = third + 1;
  while (fourth < n && CGAL::coplanar(points[0], points[second], points[third], points[fourth])) {
    ++fourth;
  }
  if (fourth == n) {
    throw InputError(fmt::format(
        "convex hull of {}: all {} points are coplanar (volume 0); a hull needs a 3-D point set",
        source, n));
  }
}

// the error for a point set whose thickness is below the merge tolerance somewhere
[[noreturn]] void ThrowFlatWithinTolerance(const std::string& source, double tolerance,
                                           double diagonal) {
  throw InputError(fmt::format(
      "convex hull of {}: the points are flat within the coplanar tolerance ({:.3g} m over a "
      "{:.6g} m bounding-box diagonal); a hull needs a 3-D point set",
      source, tolerance, diagonal));
}

// The exact hull as plain arrays: triangles (outward), the triangle across each edge (k, k + 1)
// and its vertex off that edge (its apex), and per vertex the triangles around it and the
// vertices joined to it (compressed rows).
struct TriangulatedHull {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> across;
  std::vector<std::array<int, 3>> apex;
  std::vector<int> fan_start;
  std::vector<int> fan;
  std::vector<int> ring_start;
  std::vector<int> ring;
};

// compressed rows of the indices 0 … n − 1 by their row `row_of[i]`, each row in increasing order
void FillRows(int rows, const std::vector<int>& row_of, std::vector<int>& start,
              std::vector<int>& values) {
  start.assign(rows + 1, 0);
  for (int row : row_of) ++start[row + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  values.resize(row_of.size());
  std::vector<int> cursor(start.begin(), start.end() - 1);
  for (int i = 0; i < static_cast<int>(row_of.size()); ++i) values[cursor[row_of[i]]++] = i;
}

// CGAL's convex_hull_3 orders part of its work by vertex handles (a std::map keyed on them, that
// is on heap addresses), so the labels of the same hull can differ from call to call (and a
// body's trajectory with the process's history).
// Relabels vertices in lexicographic order of their coordinates (hull vertices are distinct),
// starts each triangle at its smallest label (keeping its winding) and sorts the triangles, so
// the hull of a point set is the same arrays in every run.
void CanonicalOrder(std::vector<Eigen::Vector3d>& points,
                    std::vector<std::array<int, 3>>& triangles) {
  const int num_vertices = static_cast<int>(points.size());
  std::vector<int> by_position(num_vertices);
  std::iota(by_position.begin(), by_position.end(), 0);
  std::sort(by_position.begin(), by_position.end(), [&](int a, int b) {
    const Eigen::Vector3d& p = points[a];
    const Eigen::Vector3d& q = points[b];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  });
  std::vector<int> vertex_label(num_vertices);
  std::vector<Eigen::Vector3d> sorted_points(num_vertices);
  for (int i = 0; i < num_vertices; ++i) {
    vertex_label[by_position[i]] = i;
    sorted_points[i] = points[by_position[i]];
  }
  points = std::move(sorted_points);
  // relabelled triangles, rotated to start at their smallest vertex, in lexicographic order
  for (std::array<int, 3>& triangle : triangles) {
    std::array<int, 3> labels;
    for (int k = 0; k < 3; ++k) labels[k] = vertex_label[triangle[k]];
    const int first =
        static_cast<int>(std::min_element(labels.begin(), labels.end()) - labels.begin());
    for (int k = 0; k < 3; ++k) triangle[k] = labels[(first + k) % 3];
  }
  std::sort(triangles.begin(), triangles.end());
}

// The exact hull's triangles (outward, indices into `points`) as plain arrays in canonical
// order, with the triangles around each vertex, its neighbours and the triangle across each edge
TriangulatedHull ToTriangulatedHull(const std::vector<Point3>& points,
                                    std::vector<std::array<int, 3>> triangles) {
  ECPSIM_DEMAND(triangles.size() >= 4);
  // the triangles are consistently wound, but the indexed triangle set's tetrahedron (a hull of
  // four points) faces inwards: a hull vertex off the first triangle tells, exactly
  const std::array<int, 3>& first = triangles.front();
  int off = 0;
  while (off == first[0] || off == first[1] || off == first[2]) ++off;
  if (CGAL::orientation(points[first[0]], points[first[1]], points[first[2]], points[off]) ==
      CGAL::POSITIVE) {
    for (std::array<int, 3>& triangle : triangles) std::swap(triangle[1], triangle[2]);
  }
  TriangulatedHull hull;
  hull.points.reserve(points.size());
  for (const Point3& p : points) hull.points.push_back(ToEigen(p));
  CanonicalOrder(hull.points, triangles);
  hull.triangles = std::move(triangles);
  const int num_vertices = static_cast<int>(hull.points.size());
  const int num_triangles = static_cast<int>(hull.triangles.size());
  // fan and ring rows filled alike, in triangle order: fan[j] holds the directed edge
  // (v, ring[j]); each directed edge occurs once on a closed surface, so each neighbour is
  // listed once
  hull.fan_start.assign(num_vertices + 1, 0);
  for (const std::array<int, 3>& tri : hull.triangles) {
    for (int v : tri) ++hull.fan_start[v + 1];
  }
  std::partial_sum(hull.fan_start.begin(), hull.fan_start.end(), hull.fan_start.begin());
  hull.ring_start = hull.fan_start;
  hull.fan.resize(3 * hull.triangles.size());
  hull.ring.resize(3 * hull.triangles.size());
  std::vector<int> third(3 * hull.triangles.size());
  std::vector<int> cursor(hull.fan_start.begin(), hull.fan_start.end() - 1);
  for (int t = 0; t < num_triangles; ++t) {
    const std::array<int, 3>& tri = hull.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int j = cursor[tri[k]]++;
      hull.fan[j] = t;
      hull.ring[j] = tri[(k + 1) % 3];
      third[j] = tri[(k + 2) % 3];
    }
  }
  // the triangle across edge (a, b) is the one holding the reverse edge (b, a)
  hull.across.resize(num_triangles);
  hull.apex.resize(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = hull.triangles[t][k];
      const int b = hull.triangles[t][(k + 1) % 3];
      int j = hull.ring_start[b];
      while (j < hull.ring_start[b + 1] && hull.ring[j] != a) ++j;
      ECPSIM_DEMAND(j < hull.ring_start[b + 1]);
      hull.across[t][k] = hull.fan[j];
      hull.apex[t][k] = third[j];
    }
  }
  return hull;
}

// The boundary of a group of triangles as one loop, counter-clockwise seen from outside, appended
// to `loop`; false if the group is not a disk (several loops or a pinched vertex).
bool AppendBoundaryLoop(const TriangulatedHull& hull, const std::vector<int>& group_of,
                        const int* first, const int* last, std::vector<std::pair<int, int>>& edges,
                        std::vector<int>& loop) {
  // a single triangle is its own loop
  if (last - first == 1) {
    loop.insert(loop.end(), hull.triangles[*first].begin(), hull.triangles[*first].end());
    return true;
  }
  edges.clear();
  for (const int* t = first; t != last; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (group_of[hull.across[*t][k]] == group_of[*t]) continue;
      edges.emplace_back(hull.triangles[*t][k], hull.triangles[*t][(k + 1) % 3]);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t k = 1; k < edges.size(); ++k) {
    if (edges[k].first == edges[k - 1].first) return false;
  }
  if (edges.empty()) return false;
  const std::size_t begin = loop.size();
  int v = edges.front().first;
  do {
    loop.push_back(v);
    const auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(v, -1));
    if (it == edges.end() || it->first != v || loop.size() - begin > edges.size()) {
      loop.resize(begin);
      return false;
    }
    v = it->second;
  } while (v != edges.front().first);
  if (loop.size() - begin != edges.size()) {
    loop.resize(begin);
    return false;
  }
  return true;
}

// Far below the merge tolerance and far above the round-off of n · v (a few 1e-16 of the largest
// coordinate): a merged face's outermost vertex is searched for among the vertices this close to
// the best one found by climbing, so that near-ties in double precision cannot make the offset
// depend on the path the climb took; and a quick test that rejects a neighbour by one point
// allows this much beyond the merge tolerance, so that round-off cannot make it stricter than the
// full test.
constexpr double kSupportSlack = 1e-12;  // dimensionless, × largest |coordinate|

// The exact hull's faces: its triangles joined across every edge whose two triangles are exactly
// coplanar (exact predicate), i.e. the true faces of the polytope of the input points, whatever
// way CGAL triangulated them. Their corners (vertices on three exact faces or more: the extreme
// points) and planes depend on the point set alone.
struct ExactFaces {
  std::vector<int> face_of;         // exact face of each triangle
  std::vector<int> triangle_start;  // the triangles of each exact face (compressed rows)
  std::vector<int> triangles;
  std::vector<int> corner_start;      // the corners of each exact face, counter-clockwise seen
  std::vector<int> corners;           // from outside, starting at its smallest label
  std::vector<Eigen::Vector3d> area;  // fan over the corners from the first: 2 × area × normal
  std::vector<char> extreme;          // per vertex: on three exact faces or more
  int size() const { return static_cast<int>(area.size()); }
};

// how many distinct values (at most 3, the count stops there) `label` takes on the triangles
// around vertex v
int DistinctAround(const TriangulatedHull& hull, const std::vector<int>& label, int v) {
  std::array<int, 3> seen{};
  int distinct = 0;
  for (int k = hull.fan_start[v]; k < hull.fan_start[v + 1] && distinct < 3; ++k) {
    const int value = label[hull.fan[k]];
    if (std::find(seen.begin(), seen.begin() + distinct, value) == seen.begin() + distinct) {
      seen[distinct++] = value;
    }
  }
  return distinct;
}

// Σ (p_k − p_0) × (p_{k+1} − p_0) over a convex polygon given as `count` labels: twice its area
// times its normal. Differences to the first corner keep a face in a coordinate plane exactly
// normal to its axis (its in-plane differences have an exact zero component).
Eigen::Vector3d FanAreaVector(const std::vector<Eigen::Vector3d>& points, const int* polygon,
                              int count) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const Eigen::Vector3d& origin = points[polygon[0]];
  for (int k = 1; k + 1 < count; ++k) {
    sum += (points[polygon[k]] - origin).cross(points[polygon[k + 1]] - origin);
  }
  return sum;
}

// appends the labels of `loop` that `keep` marks, rotated to start at the smallest of them
void AppendCornersFromSmallest(const std::vector<int>& loop, const std::vector<char>& keep,
                               std::vector<int>& corners) {
  const std::size_t first = corners.size();
  for (int v : loop) {
    if (keep[v]) corners.push_back(v);
  }
  std::rotate(corners.begin() + first, std::min_element(corners.begin() + first, corners.end()),
              corners.end());
}

ExactFaces FindExactFaces(const TriangulatedHull& hull,
                          const std::vector<Eigen::Vector3d>& area_normals) {
  const int num_triangles = static_cast<int>(hull.triangles.size());
  const int num_points = static_cast<int>(hull.points.size());
  const auto point = [&](int v) {
    return Point3(hull.points[v].x(), hull.points[v].y(), hull.points[v].z());
  };
  // union–find over the exactly flat edges; each edge is tested once, from its lower triangle
  std::vector<int> parent(num_triangles);
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (int t = 0; t < num_triangles; ++t) {
    const std::array<int, 3>& tri = hull.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int u = hull.across[t][k];
      // every edge takes the exact test (its static filter decides most at once): a cheaper
      // test on computed normals could misjudge a sliver whose normal is mostly round-off
      if (u < t) continue;
      if (CGAL::orientation(point(tri[0]), point(tri[1]), point(tri[2]), point(hull.apex[t][k])) !=
          CGAL::COPLANAR) {
        continue;
      }
      const int a = root(t);
      const int b = root(u);
      parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // faces numbered in the order of their first triangles
  ExactFaces faces;
  faces.face_of.resize(num_triangles);
  int num_faces = 0;
  for (int t = 0; t < num_triangles; ++t) {
    const int r = root(t);
    faces.face_of[t] = r == t ? num_faces++ : faces.face_of[r];
  }
  FillRows(num_faces, faces.face_of, faces.triangle_start, faces.triangles);
  faces.extreme.resize(num_points);
  for (int v = 0; v < num_points; ++v) {
    faces.extreme[v] = DistinctAround(hull, faces.face_of, v) >= 3;
  }
  // corners: a lone triangle's are its vertices (a vertex on fewer than three exact faces would
  // make it degenerate), starting at the smallest already; a larger face's are the extreme points
  // on its boundary
  faces.corner_start.reserve(num_faces + 1);
  faces.corner_start.push_back(0);
  faces.corners.reserve(3 * num_faces);
  faces.area.resize(num_faces);
  std::vector<std::pair<int, int>> edges;
  std::vector<int> loop;
  for (int f = 0; f < num_faces; ++f) {
    const int* first = faces.triangles.data() + faces.triangle_start[f];
    const int* last = faces.triangles.data() + faces.triangle_start[f + 1];
    const std::size_t begin = faces.corners.size();
    if (last - first == 1) {
      const std::array<int, 3>& tri = hull.triangles[*first];
      faces.corners.insert(faces.corners.end(), tri.begin(), tri.end());
      faces.area[f] = area_normals[*first];
    } else {
      loop.clear();
      ECPSIM_DEMAND(AppendBoundaryLoop(hull, faces.face_of, first, last, edges, loop));
      AppendCornersFromSmallest(loop, faces.extreme, faces.corners);
      ECPSIM_DEMAND(faces.corners.size() - begin >= 3);
      faces.area[f] = FanAreaVector(hull.points, faces.corners.data() + begin,
                                    static_cast<int>(faces.corners.size() - begin));
    }
    faces.corner_start.push_back(static_cast<int>(faces.corners.size()));
  }
  return faces;
}

// how many seeds ahead the coplanar merge starts fetching a seed's data: enough to cover a few
// memory latencies at a seed's few ns of arithmetic, few enough to stay in the L1 cache
constexpr int kSeedsAhead = 16;

// Grows planar groups of exact faces from the largest first (their normals are the most
// accurate): a neighbour joins when all its corners lie within `tolerance` of the seed's plane,
// so a group is a union of whole exact faces. Testing distances to the group's plane, not
// normals of neighbours pairwise, keeps a finely tessellated curved surface from drifting into
// one face. Returns the group of each exact face; `seed_rank` receives the place in `order` of
// each group's seed (its largest exact face).
std::vector<int> GrowCoplanarGroups(const TriangulatedHull& hull, const ExactFaces& faces,
                                    const std::vector<int>& order, double tolerance, double slack,
                                    std::vector<int>& seed_rank) {
  // what a seed needs in one record, filled in memory order (the seeds come scattered, in order
  // of area): its plane (a zero normal for a face whose area vector evaluates to zero) and its
  // triangles (the range in faces.triangles, the first of them)
  struct Seed {
    Eigen::Vector3d n;
    double d;
    int begin;
    int end;
    int first;
  };
  std::vector<Seed> seeds(faces.size());
  for (int f = 0; f < faces.size(); ++f) {
    Seed& seed = seeds[f];
    seed.begin = faces.triangle_start[f];
    seed.end = faces.triangle_start[f + 1];
    seed.first = faces.triangles[seed.begin];
    const double norm = faces.area[f].norm();
    seed.n = norm == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(faces.area[f] / norm);
    seed.d = norm == 0 ? 0.0 : seed.n.dot(hull.points[faces.corners[faces.corner_start[f]]]);
  }
  std::vector<int> group_of(faces.size(), -1);
  seed_rank.clear();
  std::vector<int> queue;
  const int num_faces = faces.size();
  for (int rank = 0; rank < num_faces; ++rank) {
    // the seeds' reads are scattered and depend on each other (record, apexes, their points):
    // fetched in stages ahead of use, they overlap instead of waiting one after the other
    if (rank + kSeedsAhead < num_faces) {
      __builtin_prefetch(&seeds[order[rank + kSeedsAhead]]);
      __builtin_prefetch(&group_of[order[rank + kSeedsAhead]]);
    }
    if (rank + kSeedsAhead / 2 < num_faces) {
      const int t = seeds[order[rank + kSeedsAhead / 2]].first;
      __builtin_prefetch(&hull.apex[t]);
      __builtin_prefetch(&hull.across[t]);
    }
    if (rank + kSeedsAhead / 4 < num_faces) {
      const int t = seeds[order[rank + kSeedsAhead / 4]].first;
      for (int v : hull.apex[t]) __builtin_prefetch(&hull.points[v]);
      for (int u : hull.across[t]) __builtin_prefetch(&faces.face_of[u]);
    }
    const int seed = order[rank];
    if (group_of[seed] >= 0) continue;
    const int group = static_cast<int>(seed_rank.size());
    seed_rank.push_back(rank);
    group_of[seed] = group;
    const Eigen::Vector3d n = seeds[seed].n;
    const double d = seeds[seed].d;
    // a zero-area seed cannot define a plane: it stays a group of its own
    if (n.isZero()) continue;
    queue.assign(1, seed);
    while (!queue.empty()) {
      const int f = queue.back();
      queue.pop_back();
      for (int j = seeds[f].begin; j < seeds[f].end; ++j) {
        const int t = faces.triangles[j];
        for (int k = 0; k < 3; ++k) {
          // most neighbours are rejected by their apex alone (one point to read): it lies in
          // the neighbour's exact face, within `tolerance` of the plane (up to round-off, far
          // below `slack`) if all that face's corners are
          if (std::abs(n.dot(hull.points[hull.apex[t][k]]) - d) > tolerance + slack) continue;
          // a neighbour facing the other way is no part of this face; one whose area vector
          // evaluates to exactly zero (collinear in doubles) joins it if its corners are on the
          // plane, else it stayed a face of its own without a normal
          const int g = faces.face_of[hull.across[t][k]];
          if (group_of[g] >= 0 || n.dot(faces.area[g]) < 0) continue;
          const bool coplanar =
              std::all_of(faces.corners.begin() + faces.corner_start[g],
                          faces.corners.begin() + faces.corner_start[g + 1],
                          [&](int v) { return std::abs(n.dot(hull.points[v]) - d) <= tolerance; });
          if (!coplanar) continue;
          group_of[g] = group;
          queue.push_back(g);
        }
      }
    }
  }
  return group_of;
}

// Largest n · v over the extreme points of the hull: climbing the (exactly convex) triangulated
// hull from `start` finds the largest n · v up to round-off (on a convex polytope a local maximum
// of a linear function is the global one); the extreme points within kSupportSlack of it are then
// visited (a cap of a convex polytope is connected), so the result does not depend on the path.
// `visited` (one entry per vertex, never equal to `stamp` before) marks the cap's vertices.
double MaxOverExtremePoints(const TriangulatedHull& hull, const std::vector<char>& extreme,
                            const Eigen::Vector3d& n, int start, double slack,
                            std::vector<int>& visited, int stamp, std::vector<int>& queue) {
  int v = start;
  double best = n.dot(hull.points[v]);
  double runner_up = -std::numeric_limits<double>::infinity();
  for (bool improved = true; improved;) {
    improved = false;
    runner_up = -std::numeric_limits<double>::infinity();
    for (int k = hull.ring_start[v]; k < hull.ring_start[v + 1]; ++k) {
      const double value = n.dot(hull.points[hull.ring[k]]);
      runner_up = std::max(runner_up, value);
      if (value > best) {
        best = value;
        v = hull.ring[k];
        improved = true;
      }
    }
  }
  const double floor = best - slack;
  // the usual case: no neighbour of the top within the slack, so the cap is the top alone
  if (runner_up < floor && extreme[v]) return best;
  double max_extreme = -std::numeric_limits<double>::infinity();
  queue.assign(1, v);
  visited[v] = stamp;
  while (!queue.empty()) {
    const int w = queue.back();
    queue.pop_back();
    if (extreme[w]) max_extreme = std::max(max_extreme, n.dot(hull.points[w]));
    for (int k = hull.ring_start[w]; k < hull.ring_start[w + 1]; ++k) {
      const int x = hull.ring[k];
      if (visited[x] == stamp || n.dot(hull.points[x]) < floor) continue;
      visited[x] = stamp;
      queue.push_back(x);
    }
  }
  ECPSIM_DEMAND(max_extreme > -std::numeric_limits<double>::infinity());
  return max_extreme;
}

}  // namespace

ConvexHull ComputeConvexHull(const std::vector<Eigen::Vector3d>& points, const std::string& source,
                             ConvexHullStageTimes* stage_times) {
  // validate before any work
  if (points.size() < 4) {
    throw InputError(fmt::format(
        "convex hull of {}: {} points given; a hull needs at least 4 points that are not coplanar",
        source, points.size()));
  }
  std::vector<Point3> cgal_points;
  cgal_points.reserve(points.size());
  Eigen::Vector3d lower = points.front();
  Eigen::Vector3d upper = points.front();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    if (!p.allFinite()) {
      throw InputError(fmt::format(
          "convex hull of {}: point {} = ({}, {}, {}) is not finite; expected finite coordinates",
          source, i, p.x(), p.y(), p.z()));
    }
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
    cgal_points.emplace_back(p.x(), p.y(), p.z());
  }
  CheckFullDimensional(cgal_points, source);
  const double diagonal = (upper - lower).norm();
  const double tolerance = kCoplanarTolerance * diagonal;
  const double slack =
      kSupportSlack * std::max(lower.cwiseAbs().maxCoeff(), upper.cwiseAbs().maxCoeff());

  // exact-predicate hull as outward triangles; the stages are timed only when asked
  const auto clock = [stage_times] { return stage_times != nullptr ? ThreadCpuSeconds() : 0.0; };
  const double hull_start = clock();
  std::vector<Point3> hull_points;
  std::vector<std::array<int, 3>> hull_triangles;
  HullTriangles output(hull_points, hull_triangles);
  CGAL::convex_hull_3(cgal_points.begin(), cgal_points.end(), output, HullTraits());
  const double hull_done = clock();
  const TriangulatedHull exact = ToTriangulatedHull(hull_points, std::move(hull_triangles));
  const double arrays_done = clock();
  const int num_triangles = static_cast<int>(exact.triangles.size());
  const int num_points = static_cast<int>(exact.points.size());

  // triangle area vectors (each from its smallest label), then the exact faces they make up
  std::vector<Eigen::Vector3d> area_normals(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    const std::array<int, 3>& tri = exact.triangles[t];
    area_normals[t] = (exact.points[tri[1]] - exact.points[tri[0]])
                          .cross(exact.points[tri[2]] - exact.points[tri[0]]);
  }
  const ExactFaces faces = FindExactFaces(exact, area_normals);
  area_normals = {};
  const int num_faces = faces.size();

  // exact faces largest first; equal areas by their first two corners (a directed hull edge,
  // so unique; labels order as coordinates do), so the order depends on the points alone.
  // Keyed by −(squared area) for boost's radix-based float_sort (several times faster than a
  // comparison sort on a million keys)
  std::vector<std::pair<double, int>> by_area(num_faces);
  for (int f = 0; f < num_faces; ++f) by_area[f] = {-faces.area[f].squaredNorm(), f};
  const auto first_edge = [&](int f) {
    const int* c = faces.corners.data() + faces.corner_start[f];
    return std::make_pair(c[0], c[1]);
  };
  boost::sort::spreadsort::float_sort(
      by_area.begin(), by_area.end(),
      [](const std::pair<double, int>& x, unsigned offset) {
        return boost::sort::spreadsort::float_mem_cast<double, std::int64_t>(x.first) >> offset;
      },
      [&](const std::pair<double, int>& a, const std::pair<double, int>& b) {
        return a.first != b.first ? a.first < b.first : first_edge(a.second) < first_edge(b.second);
      });
  std::vector<int> order(num_faces);
  std::vector<int> rank(num_faces);
  for (int k = 0; k < num_faces; ++k) {
    order[k] = by_area[k].second;
    rank[order[k]] = k;
  }
  by_area = {};

  // a set flat within the tolerance has its largest faces on the flat sides
  for (int k = 0; k < std::min<int>(kFlatnessProbes, num_faces); ++k) {
    const Eigen::Vector3d n = faces.area[order[k]].normalized();
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -lowest;
    for (const Eigen::Vector3d& p : exact.points) {
      lowest = std::min(lowest, n.dot(p));
      highest = std::max(highest, n.dot(p));
    }
    if (highest - lowest <= tolerance) ThrowFlatWithinTolerance(source, tolerance, diagonal);
  }

  // Merge coplanar exact faces, then check that every merged face keeps three corners (vertices
  // on three or more faces; the others sit inside a face or on a straight edge between two).
  // Where the tolerance merged a sliver between two nearly parallel faces that check fails: the
  // offending groups and their neighbours fall back to single exact faces until it holds, which
  // it does at the latest for the exact faces themselves.
  std::vector<int> seed_rank;
  const std::vector<int> face_group =
      GrowCoplanarGroups(exact, faces, order, tolerance, slack, seed_rank);
  order = {};
  // the groups renumbered in the order of their first triangles, so that the passes below read
  // the arrays almost in order; `key` keeps each group's place in the output (the rank of its
  // largest exact face)
  int num_groups = 0;
  std::vector<int> renumbered(seed_rank.size(), -1);
  std::vector<int> key;
  key.reserve(seed_rank.size());
  std::vector<int> group_of(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    const int g = face_group[faces.face_of[t]];
    if (renumbered[g] < 0) {
      renumbered[g] = num_groups++;
      key.push_back(seed_rank[g]);
    }
    group_of[t] = renumbered[g];
  }
  renumbered = {};
  seed_rank = {};
  std::vector<int> group_start;
  std::vector<int> group_triangles;
  std::vector<int> loop_start;
  std::vector<int> loops;
  std::vector<char> corner(num_points, 0);
  std::vector<std::pair<int, int>> edges;
  std::vector<int> to_split;
  std::vector<int> split_faces;
  for (;;) {
    FillRows(num_groups, group_of, group_start, group_triangles);
    to_split.clear();
    loop_start.assign(1, 0);
    loops.clear();
    loops.reserve(3 * static_cast<std::size_t>(num_groups));
    for (int g = 0; g < num_groups; ++g) {
      const int* first = group_triangles.data() + group_start[g];
      const int* last = group_triangles.data() + group_start[g + 1];
      if (!AppendBoundaryLoop(exact, group_of, first, last, edges, loops)) to_split.push_back(g);
      loop_start.push_back(static_cast<int>(loops.size()));
    }
    if (to_split.empty()) {
      // a corner has three distinct groups around it
      for (int v = 0; v < num_points; ++v) corner[v] = DistinctAround(exact, group_of, v) >= 3;
      for (int g = 0; g < num_groups; ++g) {
        const auto corners =
            std::count_if(loops.begin() + loop_start[g], loops.begin() + loop_start[g + 1],
                          [&](int v) { return corner[v] != 0; });
        if (corners >= 3) continue;
        to_split.push_back(g);
        for (int j = loop_start[g]; j < loop_start[g + 1]; ++j) {
          const int v = loops[j];
          for (int k = exact.fan_start[v]; k < exact.fan_start[v + 1]; ++k) {
            to_split.push_back(group_of[exact.fan[k]]);
          }
        }
      }
    }
    if (to_split.empty()) break;
    std::sort(to_split.begin(), to_split.end());
    to_split.erase(std::unique(to_split.begin(), to_split.end()), to_split.end());
    // each exact face of a split group becomes a group of its own (the largest keeps the group)
    for (int g : to_split) {
      split_faces.clear();
      for (int k = group_start[g]; k < group_start[g + 1]; ++k) {
        split_faces.push_back(faces.face_of[group_triangles[k]]);
      }
      std::sort(split_faces.begin(), split_faces.end(),
                [&](int a, int b) { return rank[a] < rank[b]; });
      split_faces.erase(std::unique(split_faces.begin(), split_faces.end()), split_faces.end());
      for (std::size_t k = 1; k < split_faces.size(); ++k) {
        const int f = split_faces[k];
        const int fresh = num_groups++;
        key.push_back(rank[f]);
        for (int j = faces.triangle_start[f]; j < faces.triangle_start[f + 1]; ++j) {
          group_of[faces.triangles[j]] = fresh;
        }
      }
    }
  }
  // output labels: the corners in label order, that is in lexicographic order of coordinates
  std::vector<int> new_index(num_points, -1);
  ConvexHull hull;
  for (int v = 0; v < num_points; ++v) {
    if (!corner[v]) continue;
    new_index[v] = static_cast<int>(hull.vertices.size());
    hull.vertices.push_back(exact.points[v]);
  }

  // each group's place among the faces: in order of their largest exact faces
  std::vector<int> place(num_groups);
  {
    std::vector<int> group_by_key(num_faces, -1);
    for (int g = 0; g < num_groups; ++g) group_by_key[key[g]] = g;
    int next = 0;
    for (int g : group_by_key) {
      if (g >= 0) place[g] = next++;
    }
  }

  // per face: corner polygon from its smallest corner, normal from that polygon, offset the largest
  // n · v over the extreme points (canonical, unlike CGAL's extra vertices on faces and edges):
  // over the group's boundary for a single exact face, whose plane supports the hull; searched over
  // the hull for a merged face, whose corners may lie inside its plane
  hull.faces.resize(num_groups);
  hull.normals.resize(num_groups);
  hull.offsets.resize(num_groups);
  std::vector<int> occurrences(hull.vertices.size(), 0);
  std::vector<int> visited(num_points, -1);
  std::vector<int> queue;
  std::vector<int> corners;
  // the polygons once more in memory order, for the adjacency
  std::vector<int> polygon_start(num_groups + 1, 0);
  std::vector<int> polygons;
  polygons.reserve(loops.size());
  for (int g = 0; g < num_groups; ++g) {
    // gathered first, so that each face allocates once
    corners.clear();
    for (int j = loop_start[g]; j < loop_start[g + 1]; ++j) {
      if (corner[loops[j]]) corners.push_back(new_index[loops[j]]);
    }
    ECPSIM_DEMAND(corners.size() >= 3);
    const int f = place[g];
    std::vector<int>& polygon = hull.faces[f];
    const auto smallest = std::min_element(corners.begin(), corners.end());
    polygon.reserve(corners.size());
    polygon.insert(polygon.end(), smallest, corners.end());
    polygon.insert(polygon.end(), corners.begin(), smallest);
    polygons.insert(polygons.end(), polygon.begin(), polygon.end());
    polygon_start[g + 1] = static_cast<int>(polygons.size());
    for (int v : polygon) ++occurrences[v];
    const Eigen::Vector3d area =
        FanAreaVector(hull.vertices, polygon.data(), static_cast<int>(polygon.size()));
    const double norm = area.norm();
    ECPSIM_DEMAND(norm > 0);
    const Eigen::Vector3d n = area / norm;
    hull.normals[f] = n;
    double offset = -std::numeric_limits<double>::infinity();
    int start = -1;
    for (int j = loop_start[g]; j < loop_start[g + 1]; ++j) {
      const int v = loops[j];
      if (!faces.extreme[v] || n.dot(exact.points[v]) <= offset) continue;
      offset = n.dot(exact.points[v]);
      start = v;
    }
    const int first_face = faces.face_of[group_triangles[group_start[g]]];
    const bool single = faces.triangle_start[first_face + 1] - faces.triangle_start[first_face] ==
                        group_start[g + 1] - group_start[g];
    hull.offsets[f] =
        single ? offset
               : MaxOverExtremePoints(exact, faces.extreme, n, start, slack, visited, g, queue);
  }

  // adjacency from the polygons (in memory order, then sorted): each hull edge is walked once in
  // each direction, so the outgoing edges list every neighbour once
  hull.vertex_faces.resize(hull.vertices.size());
  hull.vertex_neighbors.resize(hull.vertices.size());
  for (std::size_t v = 0; v < hull.vertices.size(); ++v) {
    hull.vertex_faces[v].reserve(occurrences[v]);
    hull.vertex_neighbors[v].reserve(occurrences[v]);
  }
  for (int g = 0; g < num_groups; ++g) {
    const int first = polygon_start[g];
    const int last = polygon_start[g + 1];
    for (int k = first; k < last; ++k) {
      hull.vertex_faces[polygons[k]].push_back(place[g]);
      hull.vertex_neighbors[polygons[k]].push_back(polygons[k + 1 < last ? k + 1 : first]);
    }
  }
  for (std::size_t v = 0; v < hull.vertices.size(); ++v) {
    std::sort(hull.vertex_faces[v].begin(), hull.vertex_faces[v].end());
    std::sort(hull.vertex_neighbors[v].begin(), hull.vertex_neighbors[v].end());
    ECPSIM_DEMAND(hull.vertex_faces[v].size() >= 3);
  }
  if (stage_times != nullptr) {
    stage_times->exact_hull = hull_done - hull_start;
    stage_times->arrays = arrays_done - hull_done;
    stage_times->merge = clock() - arrays_done;
  }
  return hull;
}

ConvexHull TranslateHull(const ConvexHull& hull, const Eigen::Vector3d& offset) {
  ConvexHull moved = hull;
  for (Eigen::Vector3d& v : moved.vertices) v += offset;
  for (std::size_t i = 0; i < moved.offsets.size(); ++i) {
    moved.offsets[i] += moved.normals[i].dot(offset);
  }
  return moved;
}

TriangleMesh TriangulateHull(const ConvexHull& hull) {
  TriangleMesh mesh;
  mesh.vertices = hull.vertices;
  // a fan from the first corner is valid because every face is a convex polygon
  for (const std::vector<int>& polygon : hull.faces) {
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      mesh.triangles.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
    }
  }
  return mesh;
}

std::vector<Eigen::Vector2d> ComputeConvexHull2D(const std::vector<Eigen::Vector2d>& points) {
  std::vector<Point2> input;
  input.reserve(points.size());
  for (const Eigen::Vector2d& p : points) {
    ECPSIM_DEMAND(p.allFinite());
    input.emplace_back(p.x(), p.y());
  }
  // convex_hull_2 returns the extreme points counter-clockwise: one point if all coincide, the
  // two ends if all are collinear
  std::vector<Point2> extreme;
  CGAL::convex_hull_2(input.begin(), input.end(), std::back_inserter(extreme));
  std::vector<Eigen::Vector2d> hull;
  hull.reserve(extreme.size());
  for (const Point2& p : extreme) hull.emplace_back(p.x(), p.y());
  return hull;
}

}  // namespace ecpsim::geometry
