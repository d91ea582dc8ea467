#include "geometry/convex_shape.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <boost/container/small_vector.hpp>

#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

// a half-space is drawn as a square slab below its plane, large enough for the paper's scenes
// (bodies within about a metre of the origin) and thick enough to read as solid ground
constexpr double kHalfSpaceDisplayHalfWidth = 5.0;  // m
constexpr double kHalfSpaceDisplayDepth = 0.1;      // m

// vertices whose direction · x is within this fraction of |direction| × (the hull's radius) of
// the best found are searched for the support: far above the rounding of a dot product (~1e-16)
// and the gaps it leaves between a local and the global maximum, so no tie escapes; a larger
// value would only search more vertices
constexpr double kSupportTieTolerance = 1e-9;  // dimensionless
// hulls with at most this many vertices are scanned for the support instead of climbed: the
// scan's dot products cost less than the climb's bookkeeping (a box's support query took ~1,900
// instructions climbing, a sixth of a resting stack's step in its broad phase), and it gives
// the same answer, the lowest-index maximizer
constexpr int kScannedHullVertices = 32;

void CheckPositive(double value, const char* what, const char* unit) {
  if (!std::isfinite(value) || value <= 0) {
    throw InputError(fmt::format("{} = {}: expected a finite value > 0 {}", what, value, unit));
  }
}

void CheckSegments(int segments, const char* shape) {
  if (segments < 3) {
    throw InputError(
        fmt::format("{} tessellation: segments = {}: expected at least 3", shape, segments));
  }
}

// Closed, outward-wound UV sphere of radius 1: poles on ±z, `segments` around and
// max(2, segments / 2) bands from pole to pole.
TriangleMesh TessellateUnitSphere(int segments) {
  const int bands = std::max(2, segments / 2);
  TriangleMesh mesh;
  mesh.vertices.push_back(Eigen::Vector3d::UnitZ());
  for (int j = 1; j < bands; ++j) {
    const double theta = EIGEN_PI * j / bands;
    for (int i = 0; i < segments; ++i) {
      const double phi = 2 * EIGEN_PI * i / segments;
      mesh.vertices.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                 std::cos(theta));
    }
  }
  mesh.vertices.push_back(-Eigen::Vector3d::UnitZ());
  const int south = static_cast<int>(mesh.vertices.size()) - 1;
  const auto ring = [segments](int j, int i) { return 1 + (j - 1) * segments + i % segments; };
  // windings follow θ̂ × φ̂ = r̂, i.e. outward
  for (int i = 0; i < segments; ++i) {
    mesh.triangles.emplace_back(0, ring(1, i), ring(1, i + 1));
    for (int j = 1; j + 1 < bands; ++j) {
      mesh.triangles.emplace_back(ring(j, i), ring(j + 1, i), ring(j + 1, i + 1));
      mesh.triangles.emplace_back(ring(j, i), ring(j + 1, i + 1), ring(j, i + 1));
    }
    mesh.triangles.emplace_back(south, ring(bands - 1, i + 1), ring(bands - 1, i));
  }
  return mesh;
}

// Right-handed frame (e1, e2, a) with a along coordinate `axis`: a cyclic permutation of x, y, z.
Eigen::Matrix3d AxisFrame(int axis) {
  Eigen::Matrix3d frame;
  for (int k = 0; k < 3; ++k) frame.col(k) = Eigen::Vector3d::Unit((axis + 1 + k) % 3);
  return frame;
}

/// f = (|y|² − R²)/(2R): ∇f = y/R has unit length on the sphere.
class SphereShape final : public ConvexShape {
 public:
  explicit SphereShape(double radius) : radius_(radius) {}

  int NumConstraints() const override { return 1; }
  double Value(int i, const Eigen::Vector3d& y) const override {
    ECPSIM_DEMAND(i == 0);
    return (y.squaredNorm() - radius_ * radius_) / (2 * radius_);
  }
  Eigen::Vector3d Gradient(int i, const Eigen::Vector3d& y) const override {
    ECPSIM_DEMAND(i == 0);
    return y / radius_;
  }
  Eigen::Matrix3d Hessian(int i, const Eigen::Vector3d&) const override {
    ECPSIM_DEMAND(i == 0);
    return Eigen::Matrix3d::Identity() / radius_;
  }
  bool IsLinear(int) const override { return false; }
  Eigen::Vector3d Support(const Eigen::Vector3d& direction) const override {
    // every point maximizes the zero direction; the centre is one of them
    const double norm = direction.norm();
    if (norm == 0) return Eigen::Vector3d::Zero();
    return radius_ * direction / norm;
  }
  std::vector<int> ConstraintsNearSupport(const Eigen::Vector3d&, int) const override {
    return {0};
  }
  TriangleMesh Tessellate(int segments) const override {
    CheckSegments(segments, "sphere");
    TriangleMesh mesh = TessellateUnitSphere(segments);
    for (Eigen::Vector3d& v : mesh.vertices) v *= radius_;
    return mesh;
  }

 private:
  double radius_;
};

/// Side f₀ = (ρ² − R²)/(2R) with ρ the distance from the axis, ends f₁ = a·y − L/2 and
/// f₂ = −a·y − L/2: each gradient has unit length where its constraint is active.
class CylinderShape final : public ConvexShape {
 public:
  CylinderShape(double radius, double length, int axis)
      : radius_(radius), half_length_(length / 2), axis_(axis) {}

  int NumConstraints() const override { return 3; }
  double Value(int i, const Eigen::Vector3d& y) const override {
    ECPSIM_DEMAND(i >= 0 && i < 3);
    if (i == 0) return (Radial(y).squaredNorm() - radius_ * radius_) / (2 * radius_);
    return i == 1 ? y[axis_] - half_length_ : -y[axis_] - half_length_;
  }
  Eigen::Vector3d Gradient(int i, const Eigen::Vector3d& y) const override {
    ECPSIM_DEMAND(i >= 0 && i < 3);
    if (i == 0) return Radial(y) / radius_;
    return i == 1 ? Eigen::Vector3d::Unit(axis_) : Eigen::Vector3d(-Eigen::Vector3d::Unit(axis_));
  }
  Eigen::Matrix3d Hessian(int i, const Eigen::Vector3d&) const override {
    ECPSIM_DEMAND(i >= 0 && i < 3);
    if (i != 0) return Eigen::Matrix3d::Zero();
    // (I − a aᵀ)/R: the side curves only across the axis
    Eigen::Matrix3d hessian = Eigen::Matrix3d::Identity();
    hessian(axis_, axis_) = 0;
    return hessian / radius_;
  }
  bool IsLinear(int i) const override {
    ECPSIM_DEMAND(i >= 0 && i < 3);
    return i != 0;
  }
  Eigen::Vector3d Support(const Eigen::Vector3d& direction) const override {
    // the rim point: an end chosen by the axial sign (the middle for a perpendicular
    // direction), the radial part along the direction's component across the axis
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    const double axial = direction[axis_];
    point[axis_] = axial > 0 ? half_length_ : (axial < 0 ? -half_length_ : 0.0);
    const Eigen::Vector3d radial = Radial(direction);
    const double norm = radial.norm();
    if (norm > 0) point += radius_ * radial / norm;
    return point;
  }
  std::vector<int> ConstraintsNearSupport(const Eigen::Vector3d&, int) const override {
    return {0, 1, 2};
  }
  TriangleMesh Tessellate(int segments) const override {
    CheckSegments(segments, "cylinder");
    const Eigen::Matrix3d frame = AxisFrame(axis_);
    TriangleMesh mesh;
    for (double s : {-half_length_, half_length_}) {
      for (int i = 0; i < segments; ++i) {
        const double phi = 2 * EIGEN_PI * i / segments;
        mesh.vertices.push_back(
            frame * Eigen::Vector3d(radius_ * std::cos(phi), radius_ * std::sin(phi), s));
      }
    }
    const int bottom_centre = 2 * segments;
    const int top_centre = bottom_centre + 1;
    mesh.vertices.push_back(frame * Eigen::Vector3d(0, 0, -half_length_));
    mesh.vertices.push_back(frame * Eigen::Vector3d(0, 0, half_length_));
    // windings follow φ̂ × a = r̂ on the side and ±a on the ends
    for (int i = 0; i < segments; ++i) {
      const int b0 = i;
      const int b1 = (i + 1) % segments;
      const int t0 = segments + b0;
      const int t1 = segments + b1;
      mesh.triangles.emplace_back(b0, b1, t1);
      mesh.triangles.emplace_back(b0, t1, t0);
      mesh.triangles.emplace_back(top_centre, t0, t1);
      mesh.triangles.emplace_back(bottom_centre, b1, b0);
    }
    return mesh;
  }

 private:
  Eigen::Vector3d Radial(const Eigen::Vector3d& y) const {
    Eigen::Vector3d radial = y;
    radial[axis_] = 0;
    return radial;
  }

  double radius_;
  double half_length_;
  int axis_;
};

/// f = (Σ (y_k/r_k)² − 1) · r_min/2: |∇f| = 1 at the ends of the shortest axis and between
/// r_min/r_max and 1 elsewhere on the boundary.
class EllipsoidShape final : public ConvexShape {
 public:
  explicit EllipsoidShape(const Eigen::Vector3d& radii)
      : radii_(radii),
        inverse_squared_(radii.cwiseAbs2().cwiseInverse()),
        scale_(radii.minCoeff() / 2) {}

  int NumConstraints() const override { return 1; }
  double Value(int i, const Eigen::Vector3d& y) const override {
    ECPSIM_DEMAND(i == 0);
    return (y.cwiseAbs2().dot(inverse_squared_) - 1) * scale_;
  }
  Eigen::Vector3d Gradient(int i, const Eigen::Vector3d& y) const override {
    ECPSIM_DEMAND(i == 0);
    return 2 * scale_ * y.cwiseProduct(inverse_squared_);
  }
  Eigen::Matrix3d Hessian(int i, const Eigen::Vector3d&) const override {
    ECPSIM_DEMAND(i == 0);
    return Eigen::Matrix3d(2 * scale_ * inverse_squared_.asDiagonal());
  }
  bool IsLinear(int) const override { return false; }
  Eigen::Vector3d Support(const Eigen::Vector3d& direction) const override {
    // maximizing d · y on the ellipsoid y = D u, |u| = 1 gives u = D d / |D d|
    const Eigen::Vector3d scaled = radii_.cwiseProduct(direction);
    const double norm = scaled.norm();
    if (norm == 0) return Eigen::Vector3d::Zero();
    return radii_.cwiseProduct(scaled) / norm;
  }
  std::vector<int> ConstraintsNearSupport(const Eigen::Vector3d&, int) const override {
    return {0};
  }
  TriangleMesh Tessellate(int segments) const override {
    CheckSegments(segments, "ellipsoid");
    TriangleMesh mesh = TessellateUnitSphere(segments);
    for (Eigen::Vector3d& v : mesh.vertices) v = v.cwiseProduct(radii_);
    return mesh;
  }

 private:
  Eigen::Vector3d radii_;
  Eigen::Vector3d inverse_squared_;  // 1/r_k², 1/m²
  double scale_;                     // r_min/2, m
};

}  // namespace

PolyhedralShape::PolyhedralShape(ConvexHull hull) : hull_(std::move(hull)) {
  ECPSIM_DEMAND(!hull_.normals.empty());
  for (const Eigen::Vector3d& v : hull_.vertices) radius_ = std::max(radius_, v.norm());
  ECPSIM_DEMAND(hull_.normals.size() == hull_.offsets.size());
  ECPSIM_DEMAND(hull_.vertex_neighbors.size() == hull_.vertices.size());
  ECPSIM_DEMAND(hull_.vertex_faces.size() == hull_.vertices.size());
}

int PolyhedralShape::NumConstraints() const { return static_cast<int>(hull_.normals.size()); }

double PolyhedralShape::Value(int i, const Eigen::Vector3d& y) const {
  ECPSIM_DEMAND(i >= 0 && i < NumConstraints());
  return hull_.normals[i].dot(y) - hull_.offsets[i];
}

Eigen::Vector3d PolyhedralShape::Gradient(int i, const Eigen::Vector3d&) const {
  ECPSIM_DEMAND(i >= 0 && i < NumConstraints());
  return hull_.normals[i];
}

Eigen::Matrix3d PolyhedralShape::Hessian(int i, const Eigen::Vector3d&) const {
  ECPSIM_DEMAND(i >= 0 && i < NumConstraints());
  return Eigen::Matrix3d::Zero();
}

// The answer is the lowest-index vertex of largest direction · x: a function of the direction
// alone. The climb's start (the vertex the last query found) only makes it faster. On a face
// (nearly) perpendicular to `direction` — a body lying flat — the climb stops at whichever vertex
// of the face it reaches first, so with a start-dependent answer every extra query moved the
// engine's hull window: a frame builder asking for the support between steps changed the
// trajectory in its last digits (ecpsim run --frames against the same run without frames).
int PolyhedralShape::SupportVertex(const Eigen::Vector3d& direction) const {
  const int count = static_cast<int>(hull_.vertices.size());
  ECPSIM_DEMAND(count > 0);
  ECPSIM_DEMAND(direction.allFinite());
  if (count <= kScannedHullVertices) {
    int best_vertex = 0;
    double best_value = direction.dot(hull_.vertices[0]);
    for (int w = 1; w < count; ++w) {
      const double value = direction.dot(hull_.vertices[w]);
      if (value > best_value) {
        best_value = value;
        best_vertex = w;
      }
    }
    return best_vertex;
  }
  const int start = last_support_vertex_.load(std::memory_order_relaxed);
  int v = (start >= 0 && start < count) ? start : 0;
  double best = direction.dot(hull_.vertices[v]);
  // greedy climbing over every vertex of the faces at v: every step strictly improves, so it
  // ends within `count` steps at a vertex no vertex of its faces exceeds — a local maximum of the
  // exact hull's edge graph (each of its triangles lies in one merged face), which on a convex
  // polytope is the global one up to rounding. Climbing along the merged polygons' edges alone
  // is not: a merged face is planar only to the coplanar tolerance, d·x can dip along its
  // boundary, and a climb stranded there missed a 52 m mesh's lowest vertex by 5 mm
  int steps = 0;
  for (bool improved = true; improved && steps <= count; ++steps) {
    improved = false;
    const int from = v;
    for (int f : hull_.vertex_faces[from]) {
      for (int w : hull_.faces[f]) {
        const double value = direction.dot(hull_.vertices[w]);
        if (value > best) {
          best = value;
          v = w;
          improved = true;
        }
      }
    }
  }
  if (steps > count || hull_.vertex_faces[v].empty()) {
    // a hand-built hull without adjacency (an isolated start) or a runaway climb: scan everything
    v = 0;
    best = direction.dot(hull_.vertices[0]);
    for (int w = 1; w < count; ++w) {
      const double value = direction.dot(hull_.vertices[w]);
      if (value > best) {
        best = value;
        v = w;
      }
    }
  } else {
    v = LowestIndexMaximumNear(direction, v, best);
  }
  last_support_vertex_.store(v, std::memory_order_relaxed);
  return v;
}

int PolyhedralShape::LowestIndexMaximumNear(const Eigen::Vector3d& direction, int v,
                                            double best) const {
  // every vertex within `tie` of the climb's end that is connected to it through such vertices:
  // they hold every exact tie (the maximizers form a face, joined by its edges) and every
  // rounding-level local maximum, so the largest of them, lowest index first, is the global
  // answer whatever vertex the climb started from
  const double tie = kSupportTieTolerance * direction.norm() * radius_;
  const double floor = best - tie;
  const auto near = [&](int w) { return direction.dot(hull_.vertices[w]) >= floor; };
  const std::vector<int>& around = hull_.vertex_neighbors[v];
  if (std::none_of(around.begin(), around.end(), near)) return v;  // a strict maximum
  std::vector<bool> seen(hull_.vertices.size(), false);  // in the set or known to be below it
  std::vector<int> open = {v};
  seen[v] = true;
  int answer = v;
  while (!open.empty()) {
    const int u = open.back();
    open.pop_back();
    for (int w : hull_.vertex_neighbors[u]) {
      if (seen[w]) continue;
      seen[w] = true;
      const double value = direction.dot(hull_.vertices[w]);
      if (value < floor) continue;
      open.push_back(w);
      if (value > best || (value == best && w < answer)) {
        best = value;
        answer = w;
      }
    }
  }
  return answer;
}

Eigen::Vector3d PolyhedralShape::Support(const Eigen::Vector3d& direction) const {
  // a half-space has no vertices: its foot point is the support along n (and a finite stand-in
  // for every other direction, in which the set is unbounded)
  if (hull_.vertices.empty()) return hull_.offsets.front() * hull_.normals.front();
  return hull_.vertices[SupportVertex(direction)];
}

std::vector<int> PolyhedralShape::ConstraintsNearSupport(const Eigen::Vector3d& direction,
                                                         int rings) const {
  ECPSIM_DEMAND(rings >= 0);
  if (hull_.vertices.empty()) return {0};
  // breadth-first over `rings` vertex rings around the support vertex: each ring is the run of
  // `visited` found from the ring before it (on the stack for the usual one or two rings: the
  // contact step asks this every step)
  boost::container::small_vector<int, 64> visited{SupportVertex(direction)};
  size_t ring_begin = 0;
  for (int r = 0; r < rings; ++r) {
    const size_t ring_end = visited.size();
    for (size_t i = ring_begin; i < ring_end; ++i) {
      for (int w : hull_.vertex_neighbors[visited[i]]) {
        if (std::find(visited.begin(), visited.end(), w) == visited.end()) visited.push_back(w);
      }
    }
    ring_begin = ring_end;
  }
  std::vector<int> faces;
  for (int v : visited) {
    faces.insert(faces.end(), hull_.vertex_faces[v].begin(), hull_.vertex_faces[v].end());
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

TriangleMesh PolyhedralShape::Tessellate(int) const {
  if (!hull_.vertices.empty()) return TriangulateHull(hull_);
  // a half-space: a square slab under its plane, centred on the foot point
  const Eigen::Vector3d n = hull_.normals.front();
  const Eigen::Vector3d u = n.unitOrthogonal();
  const Eigen::Vector3d v = n.cross(u);
  const Eigen::Vector3d foot = hull_.offsets.front() * n;
  std::vector<Eigen::Vector3d> corners;
  for (double s : {-1.0, 1.0}) {
    for (double t : {-1.0, 1.0}) {
      for (double depth : {0.0, kHalfSpaceDisplayDepth}) {
        corners.push_back(foot + kHalfSpaceDisplayHalfWidth * (s * u + t * v) - depth * n);
      }
    }
  }
  return TriangulateHull(ComputeConvexHull(corners, "half-space display slab"));
}

std::shared_ptr<PolyhedralShape> MakeBox(const Eigen::Vector3d& half_extents) {
  if (!half_extents.allFinite() || (half_extents.array() <= 0).any()) {
    throw InputError(fmt::format("box half extents = ({}, {}, {}): expected finite values > 0 m",
                                 half_extents.x(), half_extents.y(), half_extents.z()));
  }
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k) {
    corners.push_back(
        half_extents.cwiseProduct(Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1)));
  }
  return std::make_shared<PolyhedralShape>(ComputeConvexHull(corners, "box"));
}

std::shared_ptr<PolyhedralShape> MakeHalfSpace(const Eigen::Vector3d& normal, double offset) {
  const double norm = normal.norm();
  if (!normal.allFinite() || !(norm > 0) || !std::isfinite(norm)) {
    throw InputError(
        fmt::format("half-space normal = ({}, {}, {}): expected a finite, non-zero "
                    "vector",
                    normal.x(), normal.y(), normal.z()));
  }
  if (!std::isfinite(offset)) {
    throw InputError(fmt::format("half-space offset = {}: expected a finite value in m", offset));
  }
  ConvexHull hull;
  hull.normals = {normal / norm};
  hull.offsets = {offset};
  return std::make_shared<PolyhedralShape>(std::move(hull));
}

std::shared_ptr<ConvexShape> MakeSphere(double radius) {
  CheckPositive(radius, "sphere radius", "m");
  return std::make_shared<SphereShape>(radius);
}

std::shared_ptr<ConvexShape> MakeCylinder(double radius, double length, int axis) {
  CheckPositive(radius, "cylinder radius", "m");
  CheckPositive(length, "cylinder length", "m");
  if (axis < 0 || axis > 2) {
    throw InputError(fmt::format("cylinder axis = {}: expected 0 (x), 1 (y) or 2 (z)", axis));
  }
  return std::make_shared<CylinderShape>(radius, length, axis);
}

std::shared_ptr<ConvexShape> MakeEllipsoid(const Eigen::Vector3d& radii) {
  if (!radii.allFinite() || (radii.array() <= 0).any()) {
    throw InputError(fmt::format("ellipsoid radii = ({}, {}, {}): expected finite values > 0 m",
                                 radii.x(), radii.y(), radii.z()));
  }
  return std::make_shared<EllipsoidShape>(radii);
}

}  // namespace ecpsim::geometry
