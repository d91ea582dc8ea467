#include "geometry/convex_hull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <ctime>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Geometry>
#include <fmt/format.h>

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
using HullTriangles = CGAL::Convex_hull_3::internal::Indexed_triangle_set<
    std::vector<Point3>, std::vector<std::array<int, 3>>>;
using HullTraits = CGAL::Convex_hull_traits_3<Kernel, HullTriangles, CGAL::Tag_true>;

// the flatness test looks at the normals of this many of the largest hull triangles
constexpr int kFlatnessProbes = 16;

Eigen::Vector3d ToEigen(const Point3& p) { return {p.x(), p.y(), p.z()}; }

// CPU time of the calling thread, s: stage times that other processes on the machine do not skew
double ThreadCpuSeconds() {
  timespec now{};
  ECPSIM_DEMAND(clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now) == 0);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// rejects point sets that cannot bound a volume, with exact predicates, before CGAL sees them
void CheckFullDimensional(const std::vector<Point3>& points, const std::string& source) {
  const std::size_t n = points.size();
  std::size_t second = 1;
  while (second < n && points[second] == points[0]) ++second;
  if (second == n) {
    throw InputError(fmt::format(
        "convex hull of {}: all {} points coincide (volume 0); a hull needs a 3-D point set", source,
        n));
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

// The exact hull as plain arrays: triangles (outward), the triangle across each edge (k, k + 1),
// and per vertex the triangles around it and the vertices joined to it (compressed rows).
struct TriangulatedHull {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> across;
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
    const int first = static_cast<int>(std::min_element(labels.begin(), labels.end()) -
                                       labels.begin());
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
  std::vector<int> cursor(hull.fan_start.begin(), hull.fan_start.end() - 1);
  for (int t = 0; t < num_triangles; ++t) {
    const std::array<int, 3>& tri = hull.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int j = cursor[tri[k]]++;
      hull.fan[j] = t;
      hull.ring[j] = tri[(k + 1) % 3];
    }
  }
  // the triangle across edge (a, b) is the one holding the reverse edge (b, a)
  hull.across.resize(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = hull.triangles[t][k];
      const int b = hull.triangles[t][(k + 1) % 3];
      int j = hull.ring_start[b];
      while (j < hull.ring_start[b + 1] && hull.ring[j] != a) ++j;
      ECPSIM_DEMAND(j < hull.ring_start[b + 1]);
      hull.across[t][k] = hull.fan[j];
    }
  }
  return hull;
}

// Grows planar groups from the largest triangles first (their normals are the most accurate):
// a neighbour joins when all its vertices lie within `tolerance` of the seed's plane. Testing
// distances to the group's plane, not normals of neighbours pairwise, keeps a finely tessellated
// curved surface from drifting into one face. Returns the group of each triangle.
std::vector<int> GrowCoplanarGroups(const TriangulatedHull& hull,
                                    const std::vector<Eigen::Vector3d>& area_normals,
                                    const std::vector<int>& order, double tolerance,
                                    int& num_groups) {
  std::vector<int> group_of(hull.triangles.size(), -1);
  num_groups = 0;
  std::vector<int> queue;
  for (int seed : order) {
    if (group_of[seed] >= 0) continue;
    const int group = num_groups++;
    group_of[seed] = group;
    const double norm = area_normals[seed].norm();
    // a zero-area seed cannot define a plane: it stays a group of its own
    if (norm == 0) continue;
    const Eigen::Vector3d n = area_normals[seed] / norm;
    const double d = n.dot(hull.points[hull.triangles[seed][0]]);
    queue.assign(1, seed);
    while (!queue.empty()) {
      const int t = queue.back();
      queue.pop_back();
      for (int u : hull.across[t]) {
        // a neighbour facing the other way is no part of this face; one whose area vector
        // evaluates to exactly zero (collinear in doubles) joins it if its vertices are on the
        // plane, else it stayed a face of its own without a normal
        if (group_of[u] >= 0 || n.dot(area_normals[u]) < 0) continue;
        const bool coplanar = std::all_of(
            hull.triangles[u].begin(), hull.triangles[u].end(),
            [&](int v) { return std::abs(n.dot(hull.points[v]) - d) <= tolerance; });
        if (!coplanar) continue;
        group_of[u] = group;
        queue.push_back(u);
      }
    }
  }
  return group_of;
}

// The boundary of a group of triangles as one loop, counter-clockwise seen from outside, appended
// to `loop`; false if the group is not a disk (several loops or a pinched vertex).
bool AppendBoundaryLoop(const TriangulatedHull& hull, const std::vector<int>& group_of,
                        const int* first, const int* last,
                        std::vector<std::pair<int, int>>& edges, std::vector<int>& loop) {
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

// Largest n · v over the hull's vertices by climbing the (exactly convex) triangulated hull from
// `start`: on a convex polytope a local maximum of a linear function is the global one.
double MaxAlong(const TriangulatedHull& hull, const Eigen::Vector3d& n, int start) {
  int v = start;
  double best = n.dot(hull.points[v]);
  for (bool improved = true; improved;) {
    improved = false;
    for (int k = hull.ring_start[v]; k < hull.ring_start[v + 1]; ++k) {
      const double value = n.dot(hull.points[hull.ring[k]]);
      if (value > best) {
        best = value;
        v = hull.ring[k];
        improved = true;
      }
    }
  }
  return best;
}

}  // namespace

ConvexHull ComputeConvexHull(const std::vector<Eigen::Vector3d>& points,
                             const std::string& source, ConvexHullStageTimes* stage_times) {
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

  // triangle area vectors, largest first
  std::vector<Eigen::Vector3d> area_normals(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    const std::array<int, 3>& tri = exact.triangles[t];
    area_normals[t] = (exact.points[tri[1]] - exact.points[tri[0]])
                          .cross(exact.points[tri[2]] - exact.points[tri[0]]);
  }
  // (squared area, triangle) keys sort without reaching back into the triangles
  std::vector<std::pair<double, int>> by_area(num_triangles);
  for (int t = 0; t < num_triangles; ++t) by_area[t] = {area_normals[t].squaredNorm(), t};
  std::sort(by_area.begin(), by_area.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::vector<int> order(num_triangles);
  for (int k = 0; k < num_triangles; ++k) order[k] = by_area[k].second;
  by_area = {};

  // a set flat within the tolerance has its largest triangles on the flat sides
  for (int k = 0; k < std::min<int>(kFlatnessProbes, num_triangles); ++k) {
    const Eigen::Vector3d n = area_normals[order[k]].normalized();
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -lowest;
    for (const Eigen::Vector3d& p : exact.points) {
      lowest = std::min(lowest, n.dot(p));
      highest = std::max(highest, n.dot(p));
    }
    if (highest - lowest <= tolerance) ThrowFlatWithinTolerance(source, tolerance, diagonal);
  }

  // Merge coplanar triangles, then check that every merged face keeps three corners (vertices
  // on three or more faces; the others sit inside a face or on a straight edge between two).
  // Where the tolerance merged a sliver between two nearly parallel faces that check fails: the
  // offending groups and their neighbours fall back to single triangles until it holds, which
  // it does at the latest for the plain triangulation.
  int num_groups = 0;
  std::vector<int> group_of = GrowCoplanarGroups(exact, area_normals, order, tolerance, num_groups);
  std::vector<int> group_start;
  std::vector<int> group_triangles;
  std::vector<int> loop_start;
  std::vector<int> loops;
  std::vector<char> corner(num_points, 0);
  std::vector<std::pair<int, int>> edges;
  for (;;) {
    FillRows(num_groups, group_of, group_start, group_triangles);
    std::vector<int> to_split;
    loop_start.assign(1, 0);
    loops.clear();
    for (int g = 0; g < num_groups; ++g) {
      const int* first = group_triangles.data() + group_start[g];
      const int* last = group_triangles.data() + group_start[g + 1];
      if (!AppendBoundaryLoop(exact, group_of, first, last, edges, loops)) to_split.push_back(g);
      loop_start.push_back(static_cast<int>(loops.size()));
    }
    if (to_split.empty()) {
      // a corner has three distinct groups around it
      for (int v = 0; v < num_points; ++v) {
        std::array<int, 3> seen{};
        int distinct = 0;
        for (int k = exact.fan_start[v]; k < exact.fan_start[v + 1] && distinct < 3; ++k) {
          const int g = group_of[exact.fan[k]];
          if (std::find(seen.begin(), seen.begin() + distinct, g) == seen.begin() + distinct) {
            seen[distinct++] = g;
          }
        }
        corner[v] = distinct >= 3;
      }
      for (int g = 0; g < num_groups; ++g) {
        const auto corners = std::count_if(loops.begin() + loop_start[g],
                                           loops.begin() + loop_start[g + 1],
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
    for (int g : to_split) {
      for (int k = group_start[g] + 1; k < group_start[g + 1]; ++k) {
        group_of[group_triangles[k]] = num_groups++;
      }
    }
  }
  std::vector<int> new_index(num_points, -1);
  ConvexHull hull;
  for (int v = 0; v < num_points; ++v) {
    if (!corner[v]) continue;
    new_index[v] = static_cast<int>(hull.vertices.size());
    hull.vertices.push_back(exact.points[v]);
  }

  // per face: corner polygon, area-weighted normal, offset over every hull vertex
  hull.faces.resize(num_groups);
  hull.normals.resize(num_groups);
  hull.offsets.resize(num_groups);
  std::vector<int> occurrences(hull.vertices.size(), 0);
  for (int g = 0; g < num_groups; ++g) {
    std::vector<int>& polygon = hull.faces[g];
    polygon.reserve(std::count_if(loops.begin() + loop_start[g], loops.begin() + loop_start[g + 1],
                                  [&](int v) { return new_index[v] >= 0; }));
    for (int j = loop_start[g]; j < loop_start[g + 1]; ++j) {
      if (new_index[loops[j]] < 0) continue;
      polygon.push_back(new_index[loops[j]]);
      ++occurrences[polygon.back()];
    }
    ECPSIM_DEMAND(polygon.size() >= 3);
    Eigen::Vector3d area_normal = Eigen::Vector3d::Zero();
    for (int k = group_start[g]; k < group_start[g + 1]; ++k) {
      area_normal += area_normals[group_triangles[k]];
    }
    const double norm = area_normal.norm();
    ECPSIM_DEMAND(norm > 0);
    const Eigen::Vector3d n = area_normal / norm;
    int start = loops[loop_start[g]];
    for (int j = loop_start[g]; j < loop_start[g + 1]; ++j) {
      if (n.dot(exact.points[loops[j]]) > n.dot(exact.points[start])) start = loops[j];
    }
    hull.normals[g] = n;
    // an unmerged triangle's plane supports the exact hull already; a merged face's normal is
    // an average, so its outermost vertex is searched for
    const bool single = group_start[g + 1] - group_start[g] == 1;
    hull.offsets[g] = single ? n.dot(exact.points[start]) : MaxAlong(exact, n, start);
  }

  // adjacency from the polygons: each hull edge is walked once in each direction, so the
  // outgoing edges list every neighbour once; faces arrive in increasing order
  hull.vertex_faces.resize(hull.vertices.size());
  hull.vertex_neighbors.resize(hull.vertices.size());
  for (std::size_t v = 0; v < hull.vertices.size(); ++v) {
    hull.vertex_faces[v].reserve(occurrences[v]);
    hull.vertex_neighbors[v].reserve(occurrences[v]);
  }
  for (int f = 0; f < num_groups; ++f) {
    const std::vector<int>& polygon = hull.faces[f];
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      hull.vertex_faces[polygon[k]].push_back(f);
      hull.vertex_neighbors[polygon[k]].push_back(polygon[(k + 1) % polygon.size()]);
    }
  }
  for (std::size_t v = 0; v < hull.vertices.size(); ++v) {
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
