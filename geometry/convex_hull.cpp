#include "geometry/convex_hull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <tuple>
#include <utility>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <fmt/format.h>
#include <Eigen/Geometry>

#include "common/cpu_clock.h"
#include "common/errors.h"
#include "common/parallel_for.h"
#include "geometry/convex_hull_stages.h"

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

  // triangle area vectors (each from its smallest label), then the exact faces they make up
  std::vector<Eigen::Vector3d> area_normals(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    const std::array<int, 3>& tri = exact.triangles[t];
    area_normals[t] = (exact.points[tri[1]] - exact.points[tri[0]])
                          .cross(exact.points[tri[2]] - exact.points[tri[0]]);
  }
  const ExactFaces faces = FindExactFaces(exact, area_normals);
  area_normals = {};

  // the exact faces ordered, merged into the hull's faces, and the hull built from them
  FaceOrder face_order = OrderFacesByArea(faces);
  CheckNotFlat(exact, faces, face_order.order, tolerance, diagonal, source);
  const MergedFaces merged = MergeFaces(exact, faces, std::move(face_order), tolerance, slack);
  ConvexHull hull = BuildHull(exact, faces, merged, slack);
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

namespace {

using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactMesh = CGAL::Surface_mesh<Exact::Point_3>;
using ExactHalfedge = ExactMesh::Halfedge_index;

// the face left of `h` as its corners, outward (the mesh is oriented outward)
std::array<Exact::Point_3, 3> FaceCorners(const ExactMesh& mesh, ExactHalfedge h) {
  return {mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
          mesh.point(mesh.target(mesh.next(h)))};
}

Eigen::Vector3d ToEigen(const Exact::Point_3& p) {
  return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
}

bool OnPlaneOf(const std::array<Exact::Point_3, 3>& face, const Exact::Point_3& p) {
  return CGAL::orientation(face[0], face[1], face[2], p) == CGAL::COPLANAR;
}

// whether the solid wraps more than half a turn round the edge of `h`: the far corner of the
// face across it lies outside the plane of the face left of `h`
bool IsReflex(const ExactMesh& mesh, ExactHalfedge h) {
  const std::array<Exact::Point_3, 3> face = FaceCorners(mesh, h);
  return CGAL::orientation(face[0], face[1], face[2],
                           mesh.point(mesh.target(mesh.next(mesh.opposite(h))))) == CGAL::POSITIVE;
}

// The cut that removes a reflex edge: the plane of a face beside it, which the solid crosses
// there. Of all such planes, the one that holds the most reflex edges, so that one cut frees
// what one cut can (the annulus where a dumbbell's disc meets its bar: all of its edges at
// once); ties go to the first in the mesh's order, so the pieces do not depend on chance.
std::optional<Exact::Plane_3> ReflexCut(const ExactMesh& mesh) {
  std::vector<ExactHalfedge> reflex;
  for (ExactMesh::Edge_index e : mesh.edges()) {
    const ExactHalfedge h = mesh.halfedge(e);
    if (IsReflex(mesh, h)) reflex.push_back(h);
  }
  if (reflex.empty()) return std::nullopt;
  // the ends in doubles, to skip the exact test for ends plainly off a plane
  std::vector<std::array<Eigen::Vector3d, 2>> ends;
  double size = 0;
  for (const ExactHalfedge h : reflex) {
    ends.push_back({ToEigen(mesh.point(mesh.source(h))), ToEigen(mesh.point(mesh.target(h)))});
    size = std::max(
        {size, ends.back()[0].lpNorm<Eigen::Infinity>(), ends.back()[1].lpNorm<Eigen::Infinity>()});
  }
  // far above the doubles' round-off of a plane through three corners of this size
  const double off_plane = 1e-9 * size;
  // each plane counted once however many of its faces border reflex edges (as a dumbbell's
  // annulus does)
  struct Counted {
    Eigen::Vector3d unit, a;
    std::array<Exact::Point_3, 3> face;
  };
  std::vector<Counted> counted;
  std::optional<std::array<Exact::Point_3, 3>> best;
  std::size_t best_count = 0;
  for (const ExactHalfedge h : reflex) {
    for (const ExactHalfedge side : {h, mesh.opposite(h)}) {
      const std::array<Exact::Point_3, 3> face = FaceCorners(mesh, side);
      const Eigen::Vector3d a = ToEigen(face[0]);
      const Eigen::Vector3d unit = (ToEigen(face[1]) - a).cross(ToEigen(face[2]) - a).normalized();
      const auto near = [&](const Eigen::Vector3d& p) {
        return std::abs(unit.dot(p - a)) <= off_plane;
      };
      const bool seen = std::any_of(counted.begin(), counted.end(), [&](const Counted& c) {
        return std::abs(std::abs(c.unit.dot(unit)) - 1) <= 1e-12 && near(c.a) &&
               OnPlaneOf(face, c.face[0]) && OnPlaneOf(face, c.face[1]) &&
               OnPlaneOf(face, c.face[2]);
      });
      if (seen) continue;
      counted.push_back({unit, a, face});
      std::size_t count = 0;
      for (std::size_t k = 0; k < reflex.size(); ++k) {
        count += near(ends[k][0]) && near(ends[k][1]) &&
                 OnPlaneOf(face, mesh.point(mesh.source(reflex[k]))) &&
                 OnPlaneOf(face, mesh.point(mesh.target(reflex[k])));
      }
      if (count > best_count) {
        best = face;
        best_count = count;
      }
    }
  }
  return Exact::Plane_3((*best)[0], (*best)[1], (*best)[2]);
}

// the solid `piece` bounds on the negative side of `plane`, as its connected solids
std::vector<ExactMesh> Clipped(const ExactMesh& piece, const Exact::Plane_3& plane) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  ExactMesh clipped = piece;
  if (!PMP::clip(clipped, plane, CGAL::parameters::clip_volume(true))) {
    throw CGAL::Failure_exception("ecpsim", "clip", __FILE__, __LINE__,
                                  "a cut left a non-manifold piece");
  }
  std::vector<ExactMesh> components;
  if (clipped.number_of_faces() > 0) PMP::split_connected_components(clipped, components);
  return components;
}

// a convex piece's corners, rounded to doubles: its vertices but those whose faces all lie in
// one plane (where a cut's cap meets a face it continues), which only slow the hull down
std::vector<Eigen::Vector3d> Corners(const ExactMesh& piece) {
  std::vector<Eigen::Vector3d> corners;
  for (ExactMesh::Vertex_index v : piece.vertices()) {
    const std::array<Exact::Point_3, 3> first = FaceCorners(piece, piece.halfedge(v));
    bool flat = true;
    for (const ExactHalfedge h : CGAL::halfedges_around_target(v, piece))
      flat = flat && OnPlaneOf(first, piece.point(piece.source(h)));
    if (flat) continue;
    corners.push_back(ToEigen(piece.point(v)));
  }
  return corners;
}

// Cuts each piece at a reflex edge until none has one, from the whole. A cut along a face's
// plane leaves both sides convex at the edge, and no later cut of either side takes that plane
// again (each side lies in one of its half-spaces), so this ends.
std::vector<std::vector<Eigen::Vector3d>> CutAtReflexEdges(ExactMesh whole) {
  std::vector<std::vector<Eigen::Vector3d>> pieces;
  std::vector<ExactMesh> pending;
  pending.push_back(std::move(whole));
  while (!pending.empty()) {
    ExactMesh piece = std::move(pending.back());
    pending.pop_back();
    const std::optional<Exact::Plane_3> cut = ReflexCut(piece);
    if (!cut) {
      pieces.push_back(Corners(piece));
      continue;
    }
    // the two sides at once
    const std::array<Exact::Plane_3, 2> sides = {*cut, cut->opposite()};
    std::array<std::vector<ExactMesh>, 2> clipped;
    ParallelFor(2, [&](std::size_t k) { clipped[k] = Clipped(piece, sides[k]); });
    for (std::vector<ExactMesh>& side : clipped)
      for (ExactMesh& component : side) pending.push_back(std::move(component));
  }
  return pieces;
}

// Whether the surface meets itself other than at the edges and corners its triangles share
// (exact predicates on the doubles, cheaper than on the lazy exact kernel's points). Two
// triangles that meet have boxes that overlap at some coordinate along the mesh's longest axis,
// so both lie in the triangles reaching below the median there or both in those reaching above:
// the two halves are checked on two threads.
bool IntersectsItself(const std::vector<Point3>& points,
                      const std::vector<std::array<std::size_t, 3>>& triangles) {
  using Surface = CGAL::Surface_mesh<Point3>;
  Surface surface;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, triangles, surface);
  Eigen::AlignedBox3d box;
  for (const Point3& p : points) box.extend(ToEigen(p));
  Eigen::Index axis = 0;
  box.sizes().maxCoeff(&axis);
  // each face's extent along the axis, and the median of their middles
  std::vector<std::array<double, 2>> extents;
  for (Surface::Face_index f : surface.faces()) {
    std::array<double, 2> extent = {INFINITY, -INFINITY};
    for (Surface::Vertex_index v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
      extent[0] = std::min(extent[0], surface.point(v)[axis]);
      extent[1] = std::max(extent[1], surface.point(v)[axis]);
    }
    extents.push_back(extent);
  }
  std::vector<double> middles;
  for (const std::array<double, 2>& extent : extents)
    middles.push_back((extent[0] + extent[1]) / 2);
  std::nth_element(middles.begin(), middles.begin() + middles.size() / 2, middles.end());
  const double median = middles[middles.size() / 2];
  std::array<std::vector<Surface::Face_index>, 2> halves;
  for (Surface::Face_index f : surface.faces()) {
    if (extents[f][0] <= median) halves[0].push_back(f);
    if (extents[f][1] >= median) halves[1].push_back(f);
  }
  std::array<bool, 2> meets = {false, false};
  ParallelFor(2, [&](std::size_t k) {
    meets[k] = CGAL::Polygon_mesh_processing::does_self_intersect(halves[k], surface);
  });
  return meets[0] || meets[1];
}

}  // namespace

std::vector<std::vector<Eigen::Vector3d>> ExactConvexPieces(const TriangleMesh& mesh,
                                                            const std::string& source) {
  std::vector<std::array<std::size_t, 3>> triangles;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    triangles.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                         static_cast<std::size_t>(t[2])});
  }
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (!PMP::is_polygon_soup_a_polygon_mesh(triangles)) {
    throw InputError(fmt::format(
        "convex decomposition of {}: its triangles do not form a closed, consistently oriented "
        "surface (an edge with more than two triangles, or two triangles wound alike across it)",
        source));
  }
  std::vector<Point3> inexact;
  for (const Eigen::Vector3d& v : mesh.vertices) inexact.emplace_back(v.x(), v.y(), v.z());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& corner = mesh.triangles[t];
    if (CGAL::collinear(inexact[corner[0]], inexact[corner[1]], inexact[corner[2]])) {
      throw InputError(fmt::format(
          "convex decomposition of {}: triangle {} has no area (its corners {}, {}, {} lie on a "
          "line); a solid's surface needs triangles that span a plane",
          source, t, corner[0], corner[1], corner[2]));
    }
  }
  std::vector<Exact::Point_3> points;
  for (const Eigen::Vector3d& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  ExactMesh whole;
  PMP::polygon_soup_to_polygon_mesh(points, triangles, whole);
  if (!CGAL::is_closed(whole)) {
    throw InputError(fmt::format(
        "convex decomposition of {}: the mesh is not closed; a solid needs a closed surface",
        source));
  }
  // CGAL's cuts ask for a surface that does not meet itself (on one that does they may crash)
  if (IntersectsItself(inexact, triangles)) {
    throw InputError(fmt::format(
        "convex decomposition of {}: the mesh intersects itself; a solid needs a surface that "
        "does not",
        source));
  }
  std::vector<std::vector<Eigen::Vector3d>> pieces;
  try {
    pieces = CutAtReflexEdges(std::move(whole));
  } catch (const CGAL::Failure_exception& e) {
    throw InputError(
        fmt::format("convex decomposition of {}: CGAL refused the mesh: {}", source, e.message()));
  }
  return pieces;
}

// the mesh as CGAL's surface mesh, the tree of its triangles, and the inside test (which keeps
// a tree of its own)
struct SolidDistance::Trees {
  using Mesh = CGAL::Surface_mesh<Point3>;
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Mesh mesh;
  Tree tree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, Kernel>> side;
};

SolidDistance::SolidDistance(const TriangleMesh& mesh, const std::string& source)
    : trees_(std::make_unique<Trees>()) {
  if (mesh.triangles.empty()) {
    throw InputError(fmt::format("distance to the solid of {}: the mesh has no triangles", source));
  }
  std::vector<Trees::Mesh::Vertex_index> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices)
    vertices.push_back(trees_->mesh.add_vertex(Point3(v.x(), v.y(), v.z())));
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (trees_->mesh.add_face(vertices[t[0]], vertices[t[1]], vertices[t[2]]) ==
        Trees::Mesh::null_face()) {
      throw InputError(fmt::format(
          "distance to the solid of {}: its triangles do not form a consistently oriented "
          "surface (triangle {} {} {})",
          source, t[0], t[1], t[2]));
    }
  }
  trees_->tree.insert(faces(trees_->mesh).first, faces(trees_->mesh).second, trees_->mesh);
  trees_->tree.accelerate_distance_queries();
  trees_->side = std::make_unique<CGAL::Side_of_triangle_mesh<Trees::Mesh, Kernel>>(trees_->mesh);
}

SolidDistance::~SolidDistance() = default;

double SolidDistance::ToSurface(const Eigen::Vector3d& p) const {
  return std::sqrt(trees_->tree.squared_distance(Point3(p.x(), p.y(), p.z())));
}

bool SolidDistance::Inside(const Eigen::Vector3d& p) const {
  return (*trees_->side)(Point3(p.x(), p.y(), p.z())) != CGAL::ON_UNBOUNDED_SIDE;
}

}  // namespace ecpsim::geometry
