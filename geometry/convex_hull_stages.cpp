#include "geometry/convex_hull_stages.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <boost/sort/spreadsort/float_sort.hpp>

#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

// how many seeds ahead the coplanar merge starts fetching a seed's data: enough to cover a few
// memory latencies at a seed's few ns of arithmetic, few enough to stay in the L1 cache
constexpr int kSeedsAhead = 16;

// the flatness test looks at the normals of this many of the largest exact faces
constexpr int kFlatnessProbes = 16;

}  // namespace

[[noreturn]] void ThrowFlatWithinTolerance(const std::string& source, double tolerance,
                                           double diagonal) {
  throw InputError(fmt::format(
      "convex hull of {}: the points are flat within the coplanar tolerance ({:.3g} m over a "
      "{:.6g} m bounding-box diagonal); a hull needs a 3-D point set",
      source, tolerance, diagonal));
}

void FillRows(int rows, const std::vector<int>& row_of, std::vector<int>& start,
              std::vector<int>& values) {
  start.assign(rows + 1, 0);
  for (int row : row_of) ++start[row + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  values.resize(row_of.size());
  std::vector<int> cursor(start.begin(), start.end() - 1);
  for (int i = 0; i < static_cast<int>(row_of.size()); ++i) values[cursor[row_of[i]]++] = i;
}

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

Eigen::Vector3d FanAreaVector(const std::vector<Eigen::Vector3d>& points, const int* polygon,
                              int count) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const Eigen::Vector3d& origin = points[polygon[0]];
  for (int k = 1; k + 1 < count; ++k) {
    sum += (points[polygon[k]] - origin).cross(points[polygon[k + 1]] - origin);
  }
  return sum;
}

void AppendCornersFromSmallest(const std::vector<int>& loop, const std::vector<char>& keep,
                               std::vector<int>& corners) {
  const std::size_t first = corners.size();
  for (int v : loop) {
    if (keep[v]) corners.push_back(v);
  }
  std::rotate(corners.begin() + first, std::min_element(corners.begin() + first, corners.end()),
              corners.end());
}

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

FaceOrder OrderFacesByArea(const ExactFaces& faces) {
  const int num_faces = faces.size();
  // keyed by −(squared area) for boost's radix-based float_sort (several times faster than a
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
  FaceOrder result;
  std::vector<int>& order = result.order;
  std::vector<int>& rank = result.rank;
  order.resize(num_faces);
  rank.resize(num_faces);
  for (int k = 0; k < num_faces; ++k) {
    order[k] = by_area[k].second;
    rank[order[k]] = k;
  }
  by_area = {};
  return result;
}

void CheckNotFlat(const TriangulatedHull& exact, const ExactFaces& faces,
                  const std::vector<int>& order, double tolerance, double diagonal,
                  const std::string& source) {
  const int num_faces = faces.size();
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
}

MergedFaces MergeFaces(const TriangulatedHull& exact, const ExactFaces& faces, FaceOrder face_order,
                       double tolerance, double slack) {
  const int num_triangles = static_cast<int>(exact.triangles.size());
  const int num_points = static_cast<int>(exact.points.size());
  std::vector<int>& order = face_order.order;
  const std::vector<int>& rank = face_order.rank;
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
  MergedFaces merged;
  merged.num_groups = num_groups;
  merged.group_of = std::move(group_of);
  merged.key = std::move(key);
  merged.group_start = std::move(group_start);
  merged.group_triangles = std::move(group_triangles);
  merged.loop_start = std::move(loop_start);
  merged.loops = std::move(loops);
  merged.corner = std::move(corner);
  return merged;
}

ConvexHull BuildHull(const TriangulatedHull& exact, const ExactFaces& faces,
                     const MergedFaces& merged, double slack) {
  const int num_points = static_cast<int>(exact.points.size());
  const int num_faces = faces.size();
  const int num_groups = merged.num_groups;
  const std::vector<int>& key = merged.key;
  const std::vector<int>& group_start = merged.group_start;
  const std::vector<int>& group_triangles = merged.group_triangles;
  const std::vector<int>& loop_start = merged.loop_start;
  const std::vector<int>& loops = merged.loops;
  const std::vector<char>& corner = merged.corner;
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
  return hull;
}

}  // namespace ecpsim::geometry
