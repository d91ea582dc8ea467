#include "geometry/patch_moments.h"

#include <Eigen/Eigenvalues>

namespace ecpsim::geometry {

using Eigen::Matrix2d;
using Eigen::Vector2d;
using Eigen::Vector3d;

PatchMoments MomentsOf(const ContactPatch& patch, const Plane& plane) {
  PatchMoments m;
  // a basis of the plane
  const Vector3d& n = plane.normal;
  const Vector3d a = std::abs(n.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  const Vector3d b1 = (a - a.dot(n) * n).normalized(), b2 = n.cross(b1);
  const Vector3d origin = plane.offset * n;
  // per polygon the signed triangles of a fan: ∫1, ∫x, ∫x xᵀ (2-D, about the plane's origin)
  double area = 0;
  Vector2d first = Vector2d::Zero();
  Matrix2d second = Matrix2d::Zero();
  for (const auto& polygon : patch.polygons) {
    if (polygon.size() < 3) continue;
    const auto in_plane = [&](const Vector3d& x) {
      return Vector2d(b1.dot(x - origin), b2.dot(x - origin));
    };
    double polygon_area = 0;
    Vector2d polygon_first = Vector2d::Zero();
    Matrix2d polygon_second = Matrix2d::Zero();
    const Vector2d p0 = in_plane(polygon[0]);
    for (size_t i = 1; i + 1 < polygon.size(); ++i) {
      const Vector2d p1 = in_plane(polygon[i]), p2 = in_plane(polygon[i + 1]);
      const double t = 0.5 * ((p1 - p0).x() * (p2 - p0).y() - (p1 - p0).y() * (p2 - p0).x());
      polygon_area += t;
      polygon_first += t * (p0 + p1 + p2) / 3;
      // ∫ x xᵀ over a triangle: A/12 (Σ p pᵀ + (Σ p)(Σ p)ᵀ)
      const Vector2d s = p0 + p1 + p2;
      polygon_second +=
          t / 12 *
          (p0 * p0.transpose() + p1 * p1.transpose() + p2 * p2.transpose() + s * s.transpose());
    }
    // the polygon's orientation about n is not known: its area is positive either way
    const double sign = polygon_area < 0 ? -1 : 1;
    area += sign * polygon_area;
    first += sign * polygon_first;
    second += sign * polygon_second;
  }
  if (!(area > 0)) return m;
  m.area = area;
  const Vector2d c = first / area;
  m.centroid = origin + c.x() * b1 + c.y() * b2;
  const Matrix2d central = second - area * c * c.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix2d> principal(central);
  // eigenvalues ascending: the larger moment first
  m.I1 = std::max(principal.eigenvalues()[1], 0.0);
  m.I2 = std::max(principal.eigenvalues()[0], 0.0);
  const Vector2d v1 = principal.eigenvectors().col(1), v2 = principal.eigenvectors().col(0);
  m.u1 = v1.x() * b1 + v1.y() * b2;
  m.u2 = v2.x() * b1 + v2.y() * b2;
  return m;
}

}  // namespace ecpsim::geometry
