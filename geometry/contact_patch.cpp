#include "geometry/contact_patch.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "common/errors.h"
#include "geometry/convex_hull.h"

namespace ecpsim::geometry {
namespace {

// a convex patch's hull area equals the area of its faces up to round-off in the shoelace sums
constexpr double kConvexAreaRelativeTolerance = 1e-9;  // dimensionless

// Plane::normal must be unit; this admits a normal normalized in single precision
constexpr double kUnitNormalTolerance = 1e-6;  // dimensionless

// plane coordinates: u, v span the plane with u × v = n, so counter-clockwise in (u, v) is
// counter-clockwise about n
struct PlaneBasis {
  Eigen::Vector3d n;
  Eigen::Vector3d u;
  Eigen::Vector3d v;
  Eigen::Vector3d origin;  // the foot point offset · n

  explicit PlaneBasis(const Plane& plane)
      : n(plane.normal),
        u(plane.normal.unitOrthogonal()),
        v(plane.normal.cross(u)),
        origin(plane.offset * plane.normal) {}
  Eigen::Vector2d ToPlane(const Eigen::Vector3d& x) const {
    return {u.dot(x - origin), v.dot(x - origin)};
  }
  Eigen::Vector3d ToWorld(const Eigen::Vector2d& p) const { return origin + p.x() * u + p.y() * v; }
};

double Cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double SignedArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    twice += Cross2(polygon[k], polygon[(k + 1) % polygon.size()]);
  }
  return twice / 2;
}

// distance from p to the segment ab in the plane
double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_squared = ab.squaredNorm();
  const double t =
      length_squared > 0 ? std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// true if `middle` lies on the segment from `before` to `after` within `tolerance`
bool IsStraightThrough(const Eigen::Vector2d& before, const Eigen::Vector2d& middle,
                       const Eigen::Vector2d& after, double tolerance) {
  return (middle - before).dot(after - middle) > 0 &&
         DistanceToSegment(middle, before, after) <= tolerance;
}

// drops vertices of a closed loop that sit on the straight line between their neighbours
template <typename Id>
std::vector<Id> DropStraightVertices(std::vector<Id> loop,
                                     const std::vector<Eigen::Vector2d>& position,
                                     double tolerance) {
  for (bool changed = true; changed && loop.size() > 3;) {
    changed = false;
    for (std::size_t k = 0; k < loop.size() && loop.size() > 3; ++k) {
      const Id before = loop[(k + loop.size() - 1) % loop.size()];
      const Id after = loop[(k + 1) % loop.size()];
      if (IsStraightThrough(position[before], position[loop[k]], position[after], tolerance)) {
        loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(k));
        changed = true;
      }
    }
  }
  return loop;
}

std::uint64_t EdgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

int Find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// the shape of the features' hull after tolerance-level noise is removed
enum class HullKind { kEmpty, kPoint, kSegment, kPolygon };

struct PlanarHull {
  HullKind kind = HullKind::kEmpty;
  std::vector<Eigen::Vector2d> points;  // 1, 2 (the extreme pair) or ≥ 3 ccw
};

PlanarHull SimplifiedHull(const std::vector<Eigen::Vector2d>& points, double tolerance) {
  PlanarHull result;
  if (points.empty()) return result;
  std::vector<Eigen::Vector2d> hull = ComputeConvexHull2D(points);
  // the farthest pair decides between a point, a segment and a polygon
  std::size_t far_a = 0;
  std::size_t far_b = 0;
  double diameter = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    for (std::size_t j = i + 1; j < hull.size(); ++j) {
      const double distance = (hull[i] - hull[j]).norm();
      if (distance > diameter) {
        diameter = distance;
        far_a = i;
        far_b = j;
      }
    }
  }
  if (diameter <= tolerance) {
    result.kind = HullKind::kPoint;
    result.points = {hull.front()};
    return result;
  }
  // width: the smallest over edges of the largest distance from the edge's line
  double width = hull.size() < 3 ? 0 : std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < hull.size() && hull.size() >= 3; ++k) {
    const Eigen::Vector2d& a = hull[k];
    const Eigen::Vector2d edge = hull[(k + 1) % hull.size()] - a;
    const double length = edge.norm();
    if (length == 0) continue;
    double largest = 0;
    for (const Eigen::Vector2d& p : hull) {
      largest = std::max(largest, std::abs(Cross2(edge, p - a)) / length);
    }
    width = std::min(width, largest);
  }
  if (width <= tolerance) {
    result.kind = HullKind::kSegment;
    result.points = {hull[far_a], hull[far_b]};
    return result;
  }
  std::vector<int> loop(hull.size());
  std::iota(loop.begin(), loop.end(), 0);
  loop = DropStraightVertices(std::move(loop), hull, tolerance);
  result.kind = HullKind::kPolygon;
  for (int k : loop) result.points.push_back(hull[k]);
  return result;
}

// true if the intervals [lo, hi] leave no gap wider than `tolerance` between min lo and max hi
bool IntervalsConnected(std::vector<std::pair<double, double>> intervals, double tolerance) {
  std::sort(intervals.begin(), intervals.end());
  double reach = intervals.front().second;
  for (const auto& [lo, hi] : intervals) {
    if (lo > reach + tolerance) return false;
    reach = std::max(reach, hi);
  }
  return true;
}

// the hull, area and mode of `patch` from its features (docs at ExtractContactPatch below)
void Classify(const PlaneBasis& basis, double tolerance, ContactPatch& patch) {
  // hull of every feature in plane coordinates
  std::vector<Eigen::Vector2d> feature_points;
  for (const auto& polygon : patch.polygons) {
    for (const Eigen::Vector3d& p : polygon) feature_points.push_back(basis.ToPlane(p));
  }
  for (const auto& segment : patch.segments) {
    for (const Eigen::Vector3d& p : segment) feature_points.push_back(basis.ToPlane(p));
  }
  for (const Eigen::Vector3d& p : patch.points) feature_points.push_back(basis.ToPlane(p));
  const PlanarHull hull = SimplifiedHull(feature_points, tolerance);
  for (const Eigen::Vector2d& p : hull.points) patch.hull.push_back(basis.ToWorld(p));
  if (hull.kind == HullKind::kPolygon) patch.area = SignedArea(hull.points);

  // the mode
  const bool only_points = patch.polygons.empty() && patch.segments.empty();
  switch (hull.kind) {
    case HullKind::kEmpty:
      patch.mode = ContactMode::kNone;
      break;
    case HullKind::kPoint:
      patch.mode = ContactMode::kPoint;
      break;
    case HullKind::kSegment: {
      if (only_points) {
        patch.mode =
            patch.points.size() == 2 ? ContactMode::kTwoPoint : ContactMode::kNonConvexLine;
        break;
      }
      // positions along the hull's line; every feature is an interval on it
      const Eigen::Vector2d origin = hull.points[0];
      const Eigen::Vector2d direction = (hull.points[1] - origin).normalized();
      const auto along = [&](const Eigen::Vector3d& p) {
        return direction.dot(basis.ToPlane(p) - origin);
      };
      std::vector<std::pair<double, double>> intervals;
      for (const auto& polygon : patch.polygons) {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -lo;
        for (const Eigen::Vector3d& p : polygon) {
          lo = std::min(lo, along(p));
          hi = std::max(hi, along(p));
        }
        intervals.emplace_back(lo, hi);
      }
      for (const auto& segment : patch.segments) {
        const double a = along(segment[0]);
        const double b = along(segment[1]);
        intervals.emplace_back(std::min(a, b), std::max(a, b));
      }
      for (const Eigen::Vector3d& p : patch.points) intervals.emplace_back(along(p), along(p));
      patch.mode = IntervalsConnected(std::move(intervals), tolerance)
                       ? ContactMode::kLine
                       : ContactMode::kNonConvexLine;
      break;
    }
    case HullKind::kPolygon:
      if (!patch.polygons.empty()) {
        const bool convex =
            std::abs(patch.area - patch.feature_area) <= kConvexAreaRelativeTolerance * patch.area;
        patch.mode = convex ? ContactMode::kConvexPatch : ContactMode::kNonConvexPatch;
      } else {
        patch.mode = only_points ? ContactMode::kMultiPoint : ContactMode::kNonConvexPatch;
      }
      break;
  }
}

}  // namespace

const char* ContactModeName(ContactMode mode) {
  switch (mode) {
    case ContactMode::kNone:
      return "none";
    case ContactMode::kPoint:
      return "point";
    case ContactMode::kTwoPoint:
      return "two-point";
    case ContactMode::kMultiPoint:
      return "multi-point";
    case ContactMode::kLine:
      return "line";
    case ContactMode::kNonConvexLine:
      return "non-convex line";
    case ContactMode::kConvexPatch:
      return "convex patch";
    case ContactMode::kNonConvexPatch:
      return "non-convex patch";
  }
  ECPSIM_DEMAND(false && "unknown ContactMode");
  return "";
}

// Features: touching vertices (signed distance ≤ tolerance) are welded within `tolerance`, so
// triangle soups and duplicated vertices count once. Triangles with three touching corners are
// grouped by shared edges; each group's boundary loops become polygons (a hole comes out as a
// separate loop; none of the paper's bodies has one), and feature_area is the summed area of the
// touching triangles (their union, as a mesh's triangles do not overlap). Touching edges outside
// any touching triangle become segments, collinear chains merged; touching vertices on no
// touching edge become points. All features are projected onto the plane.
//
// Modes, from the hull of all features with tolerance-level noise removed:
//   no touching vertex → none; hull within `tolerance` of one point → point;
//   hull a segment (width ≤ tolerance): only points → two-point for 2 points, non-convex line
//     for ≥ 3 (collinear points with gaps, as ContactMode documents); otherwise the features'
//     extents along the line covering it without gaps → line, else non-convex line;
//   hull a polygon: with polygons, hull area = feature area within a relative 1e-9 → convex
//     patch, else non-convex patch; only points → multi-point; segments → non-convex patch.
double ContactPatchTolerance(const TriangleMesh& mesh) {
  ECPSIM_DEMAND(!mesh.vertices.empty());
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return kContactPatchRelTolerance * (hi - lo).norm();
}

ContactPatch ExtractContactPatch(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WB,
                                 const Plane& plane) {
  return ExtractContactPatch(mesh, X_WB, plane, ContactPatchTolerance(mesh));
}

ContactPatch ExtractContactPatch(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WB,
                                 const Plane& plane, double tolerance) {
  ECPSIM_DEMAND(std::isfinite(tolerance) && tolerance > 0);
  ECPSIM_DEMAND(plane.normal.allFinite() &&
                std::abs(plane.normal.norm() - 1) <= kUnitNormalTolerance);
  ECPSIM_DEMAND(std::isfinite(plane.offset) && X_WB.matrix().allFinite());
  const PlaneBasis basis(plane);

  // touching vertices, projected and welded: sweep in u order, join the first cluster within reach
  std::vector<int> touching;
  std::vector<Eigen::Vector3d> projected(mesh.vertices.size());
  std::vector<Eigen::Vector2d> plane_point(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d p_W = X_WB * mesh.vertices[i];
    const double distance = plane.normal.dot(p_W) - plane.offset;
    if (distance > tolerance) continue;
    projected[i] = p_W - distance * plane.normal;
    plane_point[i] = basis.ToPlane(projected[i]);
    touching.push_back(static_cast<int>(i));
  }
  std::sort(touching.begin(), touching.end(),
            [&](int a, int b) { return plane_point[a].x() < plane_point[b].x(); });
  std::vector<int> cluster_of(mesh.vertices.size(), -1);
  std::vector<Eigen::Vector2d> cluster_uv;
  std::vector<Eigen::Vector3d> cluster_xyz;
  for (int i : touching) {
    int found = -1;
    for (int c = static_cast<int>(cluster_uv.size()) - 1; c >= 0; --c) {
      if (cluster_uv[c].x() < plane_point[i].x() - tolerance) break;
      if ((cluster_uv[c] - plane_point[i]).norm() <= tolerance) {
        found = c;
        break;
      }
    }
    if (found < 0) {
      found = static_cast<int>(cluster_uv.size());
      cluster_uv.push_back(plane_point[i]);
      cluster_xyz.push_back(projected[i]);
    }
    cluster_of[i] = found;
  }
  ContactPatch patch;
  if (cluster_uv.empty()) return patch;

  // touching edges with the number of touching triangles on each
  std::unordered_map<std::uint64_t, int> edge_triangles;
  std::vector<std::array<int, 3>> touching_triangles;
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    const std::array<int, 3> c = {cluster_of[triangle[0]], cluster_of[triangle[1]],
                                  cluster_of[triangle[2]]};
    const bool all_distinct = c[0] != c[1] && c[1] != c[2] && c[2] != c[0];
    const bool face = c[0] >= 0 && c[1] >= 0 && c[2] >= 0 && all_distinct;
    for (int k = 0; k < 3; ++k) {
      const int a = c[k];
      const int b = c[(k + 1) % 3];
      if (a < 0 || b < 0 || a == b) continue;
      edge_triangles[EdgeKey(a, b)] += face ? 1 : 0;
    }
    if (face) touching_triangles.push_back(c);
  }

  // polygons: touching triangles joined across shared edges, boundary edges used once
  const int num_faces = static_cast<int>(touching_triangles.size());
  std::vector<int> parent(num_faces);
  std::iota(parent.begin(), parent.end(), 0);
  std::unordered_map<std::uint64_t, int> first_triangle;
  for (int t = 0; t < num_faces; ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto key = EdgeKey(touching_triangles[t][k], touching_triangles[t][(k + 1) % 3]);
      const auto [it, inserted] = first_triangle.emplace(key, t);
      if (!inserted) parent[Find(parent, t)] = Find(parent, it->second);
    }
    const Eigen::Vector2d& a = cluster_uv[touching_triangles[t][0]];
    patch.feature_area += std::abs(Cross2(cluster_uv[touching_triangles[t][1]] - a,
                                          cluster_uv[touching_triangles[t][2]] - a)) /
                          2;
  }
  std::unordered_map<int, std::vector<std::pair<int, int>>> boundary_of_group;
  for (const auto& [key, t] : first_triangle) {
    if (edge_triangles.at(key) != 1) continue;
    boundary_of_group[Find(parent, t)].emplace_back(static_cast<int>(key >> 32),
                                                    static_cast<int>(key & 0xffffffffu));
  }
  std::vector<int> group_ids;
  for (const auto& entry : boundary_of_group) group_ids.push_back(entry.first);
  std::sort(group_ids.begin(), group_ids.end());
  for (int group : group_ids) {
    // walk the boundary edges into closed loops
    std::unordered_map<int, std::vector<int>> next;
    for (const auto& [a, b] : boundary_of_group[group]) {
      next[a].push_back(b);
      next[b].push_back(a);
    }
    std::unordered_set<std::uint64_t> used;
    for (const auto& [a, b] : boundary_of_group[group]) {
      if (!used.insert(EdgeKey(a, b)).second) continue;
      std::vector<int> loop = {a};
      for (int current = b; current != a;) {
        loop.push_back(current);
        int following = -1;
        for (int w : next[current]) {
          if (used.insert(EdgeKey(current, w)).second) {
            following = w;
            break;
          }
        }
        if (following < 0) break;
        current = following;
      }
      loop = DropStraightVertices(std::move(loop), cluster_uv, tolerance);
      if (loop.size() < 3) continue;
      std::vector<Eigen::Vector2d> corners;
      for (int c : loop) corners.push_back(cluster_uv[c]);
      if (SignedArea(corners) < 0) std::reverse(loop.begin(), loop.end());
      std::vector<Eigen::Vector3d> polygon;
      for (int c : loop) polygon.push_back(cluster_xyz[c]);
      patch.polygons.push_back(std::move(polygon));
    }
  }

  // segments: touching edges in no touching triangle, chained through straight degree-2 vertices
  std::unordered_map<int, std::vector<int>> segment_neighbors;
  std::vector<bool> on_edge(cluster_uv.size(), false);
  for (const auto& [key, faces] : edge_triangles) {
    const int a = static_cast<int>(key >> 32);
    const int b = static_cast<int>(key & 0xffffffffu);
    on_edge[a] = on_edge[b] = true;
    if (faces != 0) continue;
    segment_neighbors[a].push_back(b);
    segment_neighbors[b].push_back(a);
  }
  const auto passes_through = [&](int c) {
    const std::vector<int>& around = segment_neighbors.at(c);
    return around.size() == 2 && IsStraightThrough(cluster_uv[around[0]], cluster_uv[c],
                                                   cluster_uv[around[1]], tolerance);
  };
  std::vector<int> segment_ends;
  for (const auto& entry : segment_neighbors) segment_ends.push_back(entry.first);
  std::sort(segment_ends.begin(), segment_ends.end());
  std::unordered_set<std::uint64_t> walked;
  for (int start : segment_ends) {
    if (passes_through(start)) continue;
    for (int first : segment_neighbors.at(start)) {
      if (!walked.insert(EdgeKey(start, first)).second) continue;
      int previous = start;
      int current = first;
      while (passes_through(current)) {
        const std::vector<int>& around = segment_neighbors.at(current);
        const int following = around[0] == previous ? around[1] : around[0];
        walked.insert(EdgeKey(current, following));
        previous = current;
        current = following;
      }
      patch.segments.push_back({cluster_xyz[start], cluster_xyz[current]});
    }
  }
  // a closed chain of straight vertices (degenerate) keeps its edges as they are
  for (int a : segment_ends) {
    for (int b : segment_neighbors.at(a)) {
      if (walked.insert(EdgeKey(a, b)).second)
        patch.segments.push_back({cluster_xyz[a], cluster_xyz[b]});
    }
  }

  // points: touching vertices on no touching edge
  for (std::size_t c = 0; c < cluster_uv.size(); ++c) {
    if (!on_edge[c]) patch.points.push_back(cluster_xyz[c]);
  }

  Classify(basis, tolerance, patch);
  return patch;
}

namespace {

using Polygon2 = std::vector<Eigen::Vector2d>;

// the part of `polygon` on the inner (left) side of the directed line a → b, the line included
// (one Sutherland–Hodgman pass)
Polygon2 ClipByHalfPlane(const Polygon2& polygon, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d edge = b - a;
  const auto side = [&](const Eigen::Vector2d& p) { return Cross2(edge, p - a); };
  Polygon2 out;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& p = polygon[k];
    const Eigen::Vector2d& q = polygon[(k + 1) % polygon.size()];
    const double sp = side(p), sq = side(q);
    if (sp >= 0) out.push_back(p);
    if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
  }
  return out;
}

// the interval of the segment p → q (parameters in [0, 1]) inside the convex ccw polygon `hull`,
// its boundary included; empty (lo > hi) if none
std::pair<double, double> SegmentInConvex(const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                                          const Polygon2& hull) {
  double lo = 0, hi = 1;
  for (std::size_t k = 0; k < hull.size() && lo <= hi; ++k) {
    const Eigen::Vector2d& a = hull[k];
    const Eigen::Vector2d edge = hull[(k + 1) % hull.size()] - a;
    if (edge.squaredNorm() == 0) continue;
    const double sp = Cross2(edge, p - a);
    const double sq = Cross2(edge, q - a);
    if (sp < 0 && sq < 0) return {1, 0};
    if (sp < 0) lo = std::max(lo, sp / (sp - sq));
    if (sq < 0) hi = std::min(hi, sp / (sp - sq));
  }
  return {lo, hi};
}

// true if `point` lies in `polygon` (any simple polygon) or within `tolerance` of its boundary
bool PolygonHolds(const Polygon2& polygon, const Eigen::Vector2d& point, double tolerance) {
  bool inside = false;
  for (std::size_t k = 0, j = polygon.size() - 1; k < polygon.size(); j = k++) {
    const Eigen::Vector2d& a = polygon[k];
    const Eigen::Vector2d& b = polygon[j];
    if (DistanceToSegment(point, a, b) <= tolerance) return true;
    if ((a.y() > point.y()) != (b.y() > point.y()) &&
        point.x() < a.x() + (b.x() - a.x()) * (point.y() - a.y()) / (b.y() - a.y())) {
      inside = !inside;
    }
  }
  return inside;
}

// the sub-intervals of the segment p → q inside `polygon` (any simple polygon), as parameters
std::vector<std::pair<double, double>> SegmentInPolygon(const Eigen::Vector2d& p,
                                                        const Eigen::Vector2d& q,
                                                        const Polygon2& polygon, double tolerance) {
  std::vector<double> cuts = {0, 1};
  const Eigen::Vector2d d = q - p;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& a = polygon[k];
    const Eigen::Vector2d e = polygon[(k + 1) % polygon.size()] - a;
    const double denominator = Cross2(d, e);
    if (denominator == 0) continue;
    const double t = Cross2(a - p, e) / denominator;
    const double s = Cross2(a - p, d) / denominator;
    if (t > 0 && t < 1 && s >= 0 && s <= 1) cuts.push_back(t);
  }
  std::sort(cuts.begin(), cuts.end());
  std::vector<std::pair<double, double>> inside;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double middle = 0.5 * (cuts[k] + cuts[k + 1]);
    if (!PolygonHolds(polygon, p + middle * d, tolerance)) continue;
    if (!inside.empty() && inside.back().second == cuts[k]) {
      inside.back().second = cuts[k + 1];
    } else {
      inside.emplace_back(cuts[k], cuts[k + 1]);
    }
  }
  return inside;
}

}  // namespace

ContactPatch IntersectContactPatches(const ContactPatch& patch, const ContactPatch& other,
                                     const Plane& plane, double tolerance) {
  ECPSIM_DEMAND(std::isfinite(tolerance) && tolerance > 0);
  const PlaneBasis basis(plane);
  ContactPatch result;
  if (patch.hull.empty() || other.hull.empty()) return result;
  Polygon2 clip;
  for (const Eigen::Vector3d& p : other.hull) clip.push_back(basis.ToPlane(p));
  if (clip.size() >= 3 && SignedArea(clip) < 0) std::reverse(clip.begin(), clip.end());
  const auto world = [&](const Eigen::Vector2d& p) { return basis.ToWorld(p); };
  const auto add_segment = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    if ((q - p).norm() <= tolerance) {
      result.points.push_back(world(p));
    } else {
      result.segments.push_back({world(p), world(q)});
    }
  };

  if (clip.size() >= 3) {
    // other's touching region is a convex polygon: clip every feature to it
    for (const auto& polygon : patch.polygons) {
      Polygon2 piece;
      for (const Eigen::Vector3d& p : polygon) piece.push_back(basis.ToPlane(p));
      for (std::size_t k = 0; k < clip.size() && piece.size() >= 3; ++k)
        piece = ClipByHalfPlane(piece, clip[k], clip[(k + 1) % clip.size()]);
      if (piece.size() < 3) continue;
      result.feature_area += std::abs(SignedArea(piece));
      std::vector<Eigen::Vector3d> corners;
      for (const Eigen::Vector2d& p : piece) corners.push_back(world(p));
      result.polygons.push_back(std::move(corners));
    }
    for (const auto& segment : patch.segments) {
      const Eigen::Vector2d p = basis.ToPlane(segment[0]), q = basis.ToPlane(segment[1]);
      const auto [lo, hi] = SegmentInConvex(p, q, clip);
      if (lo <= hi) add_segment(p + lo * (q - p), p + hi * (q - p));
    }
    for (const Eigen::Vector3d& point : patch.points) {
      if (PolygonHolds(clip, basis.ToPlane(point), tolerance)) result.points.push_back(point);
    }
  } else if (clip.size() == 2) {
    // other touches along a segment (a cylinder's side): that segment where this touches too
    const Eigen::Vector2d p = clip[0], q = clip[1];
    for (const auto& polygon : patch.polygons) {
      Polygon2 piece;
      for (const Eigen::Vector3d& x : polygon) piece.push_back(basis.ToPlane(x));
      for (const auto& [lo, hi] : SegmentInPolygon(p, q, piece, tolerance))
        add_segment(p + lo * (q - p), p + hi * (q - p));
    }
    for (const auto& segment : patch.segments) {
      const Eigen::Vector2d a = basis.ToPlane(segment[0]), b = basis.ToPlane(segment[1]);
      for (const auto& [lo, hi] : SegmentInPolygon(p, q, {a, b}, tolerance))
        add_segment(p + lo * (q - p), p + hi * (q - p));
    }
    for (const Eigen::Vector3d& point : patch.points) {
      if (DistanceToSegment(basis.ToPlane(point), p, q) <= tolerance)
        result.points.push_back(point);
    }
  } else {
    // other touches at a point: it, where this touches too
    bool held = false;
    for (const auto& polygon : patch.polygons) {
      Polygon2 piece;
      for (const Eigen::Vector3d& x : polygon) piece.push_back(basis.ToPlane(x));
      held |= PolygonHolds(piece, clip[0], tolerance);
    }
    for (const auto& segment : patch.segments) {
      held |= DistanceToSegment(clip[0], basis.ToPlane(segment[0]), basis.ToPlane(segment[1])) <=
              tolerance;
    }
    for (const Eigen::Vector3d& point : patch.points)
      held |= (basis.ToPlane(point) - clip[0]).norm() <= tolerance;
    if (held) result.points.push_back(world(clip[0]));
  }
  if (result.polygons.empty() && result.segments.empty() && result.points.empty()) return result;
  Classify(basis, tolerance, result);
  return result;
}

// The distance from `point` to the hull, a planar convex set in 3-D: the in-plane distance to the
// polygon (zero inside), segment or point, combined with the height above the plane.
bool PatchHullContains(const ContactPatch& patch, const Plane& plane, const Eigen::Vector3d& point,
                       double tolerance) {
  if (patch.hull.empty()) return false;
  const PlaneBasis basis(plane);
  const Eigen::Vector2d p = basis.ToPlane(point);
  std::vector<Eigen::Vector2d> hull;
  for (const Eigen::Vector3d& corner : patch.hull) hull.push_back(basis.ToPlane(corner));

  // distance within the plane: zero inside a polygon, else to the nearest edge (or the point)
  double in_plane = 0;
  if (hull.size() == 1) {
    in_plane = (p - hull[0]).norm();
  } else if (hull.size() == 2) {
    in_plane = DistanceToSegment(p, hull[0], hull[1]);
  } else {
    bool inside = true;
    in_plane = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < hull.size(); ++k) {
      const Eigen::Vector2d& a = hull[k];
      const Eigen::Vector2d& b = hull[(k + 1) % hull.size()];
      if (Cross2(b - a, p - a) < 0) inside = false;
      in_plane = std::min(in_plane, DistanceToSegment(p, a, b));
    }
    if (inside) in_plane = 0;
  }
  const double height = plane.normal.dot(point) - plane.offset;
  return std::hypot(in_plane, height) <= tolerance;
}

}  // namespace ecpsim::geometry
