#pragma once
// Convex sets described by inequalities f_i(y) ≤ 0 with gradients and Hessians: the polyhedral
// hull of a mesh and the smooth primitives (sphere, cylinder, ellipsoid; a box is polyhedral).

#include <atomic>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "geometry/convex_hull.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// {y : f_i(y) ≤ 0 for all i} in its own frame (a body frame with origin at the centre of mass,
/// or the world frame for a fixed obstacle). Every f_i is convex; on the boundary |∇f_i| = 1 for
/// the active constraint so that multipliers have comparable scales.
class ConvexShape {
 public:
  virtual ~ConvexShape() = default;

  virtual int NumConstraints() const = 0;
  virtual double Value(int i, const Eigen::Vector3d& y) const = 0;
  virtual Eigen::Vector3d Gradient(int i, const Eigen::Vector3d& y) const = 0;
  /// Zero for linear constraints.
  virtual Eigen::Matrix3d Hessian(int i, const Eigen::Vector3d& y) const = 0;
  virtual bool IsLinear(int i) const = 0;

  /// A point of the set maximizing direction · y (direction need not be unit).
  virtual Eigen::Vector3d Support(const Eigen::Vector3d& direction) const = 0;

  /// Indices of the constraints that can be active at the support feature in `direction`: for a
  /// polyhedron the faces around the support vertex grown by `rings` vertex rings; for a smooth
  /// primitive every constraint. Sorted, unique.
  virtual std::vector<int> ConstraintsNearSupport(const Eigen::Vector3d& direction,
                                                  int rings) const = 0;

  /// A closed triangle mesh of the boundary for display (smooth shapes with `segments` around).
  virtual TriangleMesh Tessellate(int segments = 48) const = 0;

  /// The shape as a polyhedron (its vertices, faces and normals), or null for a smooth one.
  virtual const class PolyhedralShape* AsPolyhedron() const { return nullptr; }

  /// Whether the shape is one linear constraint: a half-space, the ground or a tilted plane
  /// (the planar and multi-patch models need one; free flight has a closed-form test for it).
  bool IsHalfSpace() const { return NumConstraints() == 1 && IsLinear(0); }
};

/// A convex polyhedron n_i · y ≤ d_i (linear constraints, f_i = n_i · y − d_i).
class PolyhedralShape final : public ConvexShape {
 public:
  explicit PolyhedralShape(ConvexHull hull);
  const ConvexHull& hull() const { return hull_; }

  int NumConstraints() const override;
  double Value(int i, const Eigen::Vector3d& y) const override;
  Eigen::Vector3d Gradient(int i, const Eigen::Vector3d& y) const override;
  Eigen::Matrix3d Hessian(int i, const Eigen::Vector3d& y) const override;
  bool IsLinear(int) const override { return true; }
  Eigen::Vector3d Support(const Eigen::Vector3d& direction) const override;
  /// The faces of `rings` vertex rings around SupportVertex(direction).
  std::vector<int> ConstraintsNearSupport(const Eigen::Vector3d& direction,
                                          int rings) const override;
  /// The lowest-index vertex maximizing direction · x: a function of `direction` alone (ties on
  /// a face perpendicular to it included), found by hill climbing over vertex_neighbors from the
  /// last support vertex found (amortized O(1) per query for slowly moving directions). Callers
  /// sharing the shape (the engine and a frame builder) cannot change each other's answers.
  int SupportVertex(const Eigen::Vector3d& direction) const;
  TriangleMesh Tessellate(int segments = 48) const override;
  const PolyhedralShape* AsPolyhedron() const override { return this; }

 private:
  // the largest of the vertices connected to `v` (value `best`) through vertices within a
  // rounding-scale tolerance of `best`, lowest index among equals (see SupportVertex)
  int LowestIndexMaximumNear(const Eigen::Vector3d& direction, int v, double best) const;

  ConvexHull hull_;
  double radius_ = 0;  // m, the largest |vertex|: the scale of near-ties
  // hill-climbing start; a cache that never changes results. Atomic (relaxed): scenes are shared
  // by simulations on several threads, and any value it holds is a valid start
  mutable std::atomic<int> last_support_vertex_{0};
};

/// Axis-aligned box centred at the origin with the given half extents (6 linear constraints).
std::shared_ptr<PolyhedralShape> MakeBox(const Eigen::Vector3d& half_extents);

/// A half-space n · x ≤ d (one linear constraint); `normal` is normalized and `offset` is d for the
/// unit normal (metres). Used for the ground and tilted planes as the convex body G. Its hull()
/// has one normal and offset and no vertices or faces; Support returns the foot point d · n for
/// every direction (the set is unbounded in all but n); Tessellate returns a 10 m square slab,
/// 0.1 m thick, under the plane, centred on the foot point.
/// @throws InputError for a non-finite or zero normal or a non-finite offset.
std::shared_ptr<PolyhedralShape> MakeHalfSpace(const Eigen::Vector3d& normal, double offset);

/// Sphere of `radius` centred at the origin: f = (|y|² − R²)/(2R).
std::shared_ptr<ConvexShape> MakeSphere(double radius);

/// Cylinder of `radius` and `length` along `axis` (0 = x, 1 = y, 2 = z), centred at the origin:
/// the side f = (ρ² − R²)/(2R) (ρ the distance from the axis) and two end planes.
std::shared_ptr<ConvexShape> MakeCylinder(double radius, double length, int axis = 2);

/// Ellipsoid with semi-axes `radii` along x, y, z: f = (Σ (y_k/r_k)² − 1) · r_min / 2.
std::shared_ptr<ConvexShape> MakeEllipsoid(const Eigen::Vector3d& radii);

}  // namespace ecpsim::geometry
