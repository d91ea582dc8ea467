#include "geometry/patch_moments.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

// in-plane coordinates about `centre`: u, v span the plane (Eigen's unitOrthogonal, as the patch
// extraction's basis), so distances are the plane's whatever the points' height above it
struct CentredBasis {
  Eigen::Vector3d u, v, centre;
  CentredBasis(const Plane& plane, const Eigen::Vector3d& c)
      : u(plane.normal.unitOrthogonal()), v(plane.normal.cross(u)), centre(c) {}
  Eigen::Vector2d operator()(const Eigen::Vector3d& x) const {
    return {u.dot(x - centre), v.dot(x - centre)};
  }
};

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// ∫ r dA over the triangle (0, a, b), signed as its area: in polar coordinates about 0 the edge
// a → b lies at distance |h| along its normal, r = |h| sec u with s = |h| tan u along the edge, and
// ∫ r dA = ∫ ρ³/3 du = (|h|³/6)[sec u tan u + ln(sec u + tan u)] = [|h| s r + |h|³ asinh(s/|h|)]/6
// between the edge's ends (an exact antiderivative: no quadrature)
double TriangleDistanceIntegral(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double length = (b - a).norm();
  if (length == 0) return 0;
  const Eigen::Vector2d e = (b - a) / length;
  const double h = Cross(a, e);  // > 0: (0, a, b) counter-clockwise
  if (h == 0) return 0;          // the centre on the edge's line: a triangle of no area
  const double d = std::abs(h);
  const auto antiderivative = [d](double s) {
    return (d * s * std::hypot(d, s) + d * d * d * std::asinh(s / d)) / 6;
  };
  const double integral = antiderivative(e.dot(b)) - antiderivative(e.dot(a));
  return h > 0 ? integral : -integral;
}

// ∫ |x| ds along the segment a → b: ∫ sqrt(h² + s²) ds = [s r + h² asinh(s/|h|)] / 2, or
// ∫ |s| ds = s|s| / 2 where the centre lies on the segment's line
double SegmentDistanceIntegral(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double length = (b - a).norm();
  if (length == 0) return 0;
  const Eigen::Vector2d e = (b - a) / length;
  const double d = std::abs(Cross(a, e));
  const auto antiderivative = [d](double s) {
    if (d == 0) return s * std::abs(s) / 2;
    return (s * std::hypot(d, s) + d * d * std::asinh(s / d)) / 2;
  };
  return antiderivative(e.dot(b)) - antiderivative(e.dot(a));
}

double SignedPolygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0;
  for (std::size_t k = 0; k < polygon.size(); ++k)
    twice += Cross(polygon[k], polygon[(k + 1) % polygon.size()]);
  return twice / 2;
}

std::vector<Eigen::Vector2d> InPlane(const std::vector<Eigen::Vector3d>& polygon,
                                     const CentredBasis& basis) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(polygon.size());
  for (const Eigen::Vector3d& x : polygon) out.push_back(basis(x));
  return out;
}

// f(a, b, a × b) for every triangle (0, a, b) of the polygons' fans about the basis's centre:
// sums over them are the signed integrals over the polygons, holes subtracted
template <typename F>
void ForEachFanTriangle(const ContactPatch& patch, const CentredBasis& basis, F&& f) {
  for (const auto& polygon : patch.polygons) {
    const std::vector<Eigen::Vector2d> p = InPlane(polygon, basis);
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Eigen::Vector2d& a = p[k];
      const Eigen::Vector2d& b = p[(k + 1) % p.size()];
      f(a, b, Cross(a, b));
    }
  }
}

double TotalSignedArea(const ContactPatch& patch, const CentredBasis& basis) {
  double area = 0;
  for (const auto& polygon : patch.polygons) area += SignedPolygonArea(InPlane(polygon, basis));
  return area;
}

}  // namespace

PatchLoad LoadedFeatures(const ContactPatch& patch) {
  // Σ a × b around closed planar loops is twice their (signed) vector area, whatever the origin
  if (!patch.polygons.empty()) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (const auto& polygon : patch.polygons)
      for (std::size_t k = 0; k < polygon.size(); ++k)
        normal += polygon[k].cross(polygon[(k + 1) % polygon.size()]);
    if (normal.norm() > 0) return PatchLoad::kArea;
  }
  if (!patch.segments.empty()) return PatchLoad::kLine;
  if (!patch.points.empty()) return PatchLoad::kPoints;
  return PatchLoad::kNone;
}

Eigen::Vector3d PatchCentroid(const ContactPatch& patch, const Plane& plane) {
  // sums about one of the patch's own points, on the plane: no cancellation of coordinates far
  // larger than the patch
  Eigen::Vector3d origin = plane.offset * plane.normal;
  if (!patch.polygons.empty() && !patch.polygons[0].empty()) {
    origin = patch.polygons[0][0];
  } else if (!patch.segments.empty()) {
    origin = patch.segments[0][0];
  } else if (!patch.points.empty()) {
    origin = patch.points[0];
  }
  origin -= (plane.normal.dot(origin) - plane.offset) * plane.normal;
  const CentredBasis basis(plane, origin);
  const auto world = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector3d(origin + p.x() * basis.u + p.y() * basis.v);
  };
  switch (LoadedFeatures(patch)) {
    case PatchLoad::kArea: {
      // Σ over each polygon's fan of triangles (0, a, b): area a × b / 2, centroid (a + b) / 3
      Eigen::Vector2d moment = Eigen::Vector2d::Zero();
      double area = 0;
      ForEachFanTriangle(patch, basis,
                         [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double twice) {
                           area += twice / 2;
                           moment += twice / 6 * (a + b);
                         });
      if (area == 0) return world(Eigen::Vector2d::Zero());
      return world(moment / area);
    }
    case PatchLoad::kLine: {
      Eigen::Vector2d moment = Eigen::Vector2d::Zero();
      double length = 0;
      for (const auto& segment : patch.segments) {
        const Eigen::Vector2d a = basis(segment[0]), b = basis(segment[1]);
        length += (b - a).norm();
        moment += (b - a).norm() * (a + b) / 2;
      }
      // segments of no length: their ends' mean
      if (length == 0) {
        for (const auto& segment : patch.segments)
          moment += (basis(segment[0]) + basis(segment[1])) / 2;
        return world(moment / static_cast<double>(patch.segments.size()));
      }
      return world(moment / length);
    }
    case PatchLoad::kPoints: {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      for (const Eigen::Vector3d& x : patch.points) sum += basis(x);
      return world(sum / static_cast<double>(patch.points.size()));
    }
    case PatchLoad::kNone:
      return world(Eigen::Vector2d::Zero());
  }
  ECPSIM_DEMAND(false && "unknown PatchLoad");
  return origin;
}

double PatchMeanDistance(const ContactPatch& patch, const Plane& plane,
                         const Eigen::Vector3d& centre) {
  const CentredBasis basis(plane, centre);
  switch (LoadedFeatures(patch)) {
    case PatchLoad::kArea: {
      // each polygon as the signed fan of triangles (centre, a, b): exact for any simple polygon
      // and, with the loops' orientation, for holes
      double integral = 0;
      for (const auto& polygon : patch.polygons) {
        const std::vector<Eigen::Vector2d> p = InPlane(polygon, basis);
        for (std::size_t k = 0; k < p.size(); ++k)
          integral += TriangleDistanceIntegral(p[k], p[(k + 1) % p.size()]);
      }
      const double area = TotalSignedArea(patch, basis);
      return area == 0 ? 0 : integral / area;
    }
    case PatchLoad::kLine: {
      double integral = 0, length = 0;
      for (const auto& segment : patch.segments) {
        const Eigen::Vector2d a = basis(segment[0]), b = basis(segment[1]);
        integral += SegmentDistanceIntegral(a, b);
        length += (b - a).norm();
      }
      if (length > 0) return integral / length;
      double sum = 0;  // segments of no length: points
      for (const auto& segment : patch.segments) sum += basis(segment[0]).norm();
      return sum / static_cast<double>(patch.segments.size());
    }
    case PatchLoad::kPoints: {
      double sum = 0;
      for (const Eigen::Vector3d& x : patch.points) sum += basis(x).norm();
      return sum / static_cast<double>(patch.points.size());
    }
    case PatchLoad::kNone:
      return 0;
  }
  ECPSIM_DEMAND(false && "unknown PatchLoad");
  return 0;
}

PatchMoments MomentsOf(const ContactPatch& patch, const Plane& plane, double width) {
  PatchMoments m;
  const PatchLoad load = LoadedFeatures(patch);
  if (load == PatchLoad::kNone) return m;
  const Eigen::Vector3d centroid = PatchCentroid(patch, plane);
  const CentredBasis basis(plane, centroid);
  double area = 0;
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  if (load == PatchLoad::kArea) {
    // Σ over each polygon's fan of triangles (0, a, b) about the centroid: area a × b / 2 and
    // ∫ x xᵀ dA = (a × b / 24) (a aᵀ + b bᵀ + (a + b)(a + b)ᵀ)
    ForEachFanTriangle(
        patch, basis, [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double twice) {
          area += twice / 2;
          second +=
              twice / 24 * (a * a.transpose() + b * b.transpose() + (a + b) * (a + b).transpose());
        });
  } else if (load == PatchLoad::kLine) {
    // a strip of the segment a → b: width × ∫ x xᵀ ds = width L / 6 (2 a aᵀ + a bᵀ + b aᵀ + 2 b bᵀ)
    for (const auto& segment : patch.segments) {
      const Eigen::Vector2d a = basis(segment[0]), b = basis(segment[1]);
      const double length = (b - a).norm();
      area += width * length;
      second +=
          width * length / 6 *
          (2 * a * a.transpose() + a * b.transpose() + b * a.transpose() + 2 * b * b.transpose());
    }
  } else {
    // a square of side `width` at each point: its own moment and the point's Steiner term
    for (const Eigen::Vector3d& x : patch.points) {
      const Eigen::Vector2d p = basis(x);
      area += width * width;
      second +=
          width * width * (p * p.transpose() + width * width / 12 * Eigen::Matrix2d::Identity());
    }
  }
  if (area == 0) return m;
  if (area < 0) {  // the loops turn clockwise about the normal
    area = -area;
    second = -second;
  }
  m.area = area;
  m.centroid = centroid;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> principal(second);
  // eigenvalues ascending: the larger moment first
  m.I1 = std::max(principal.eigenvalues()[1], 0.0);
  m.I2 = std::max(principal.eigenvalues()[0], 0.0);
  const Eigen::Vector2d v1 = principal.eigenvectors().col(1), v2 = principal.eigenvectors().col(0);
  m.u1 = v1.x() * basis.u + v1.y() * basis.v;
  m.u2 = v2.x() * basis.u + v2.y() * basis.v;
  return m;
}

}  // namespace ecpsim::geometry
