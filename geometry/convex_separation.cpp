#include "geometry/convex_separation.h"

#include <cmath>

#include <ccd/ccd.h>

#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

// GJK's iterations before it gives up: it ends in a handful on polytopes and converges
// geometrically on smooth shapes; a query that needs more is degenerate at round-off level
constexpr unsigned long kMaxGjkIterations = 500;

// one shape as libccd sees it: its support function in coordinates relative to `origin` and
// divided by `unit`, so that the tolerances are relative and far-away coordinates cancel
struct PosedShape {
  const ConvexShape* shape;
  Eigen::Matrix3d R;
  Eigen::Vector3d p;  // its frame's origin, in the query's coordinates
  double grow = 0;    // the shape grown by a ball of this radius, in the query's units
};

void Support(const void* object, const ccd_vec3_t* direction, ccd_vec3_t* point) {
  const auto& s = *static_cast<const PosedShape*>(object);
  const Eigen::Vector3d d(direction->v[0], direction->v[1], direction->v[2]);
  Eigen::Vector3d x = s.p + s.R * s.shape->Support(s.R.transpose() * d);
  if (s.grow > 0 && d.squaredNorm() > 0) x += s.grow * d.normalized();
  ccdVec3Set(point, x.x(), x.y(), x.z());
}

// GJK's first direction: the line of the shapes' origins, which for two boxes side by side is
// the separating axis at once
void FirstDirection(const void* a, const void* b, ccd_vec3_t* direction) {
  const Eigen::Vector3d d =
      static_cast<const PosedShape*>(b)->p - static_cast<const PosedShape*>(a)->p;
  if (d.squaredNorm() > 0) {
    ccdVec3Set(direction, d.x(), d.y(), d.z());
  } else {
    ccdVec3Set(direction, 1, 0, 0);
  }
}

// libccd's query settings for shapes posed as PosedShape
ccd_t CcdQuery() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.first_dir = FirstDirection;
  ccd.support1 = Support;
  ccd.support2 = Support;
  ccd.max_iterations = kMaxGjkIterations;
  ccd.epa_tolerance = kPenetrationRelTolerance;
  ccd.dist_tolerance = kPenetrationRelTolerance;
  return ccd;
}

// the point of `shape` at X farthest along `direction` (world)
Eigen::Vector3d WorldSupport(const ConvexShape& shape, const Eigen::Isometry3d& X,
                             const Eigen::Vector3d& direction) {
  return X * shape.Support(X.linear().transpose() * direction);
}

}  // namespace

AxisSeparation SeparationAlong(const ConvexShape& a, const Eigen::Isometry3d& X_a,
                               const ConvexShape& b, const Eigen::Isometry3d& X_b,
                               const Eigen::Vector3d& axis) {
  ECPSIM_DEMAND(!a.IsHalfSpace() && !b.IsHalfSpace());
  const Eigen::Vector3d lowest_a = WorldSupport(a, X_a, -axis);
  const Eigen::Vector3d highest_b = WorldSupport(b, X_b, axis);
  return {axis, axis.dot(lowest_a - highest_b)};
}

AxisSeparation BestSeparatingAxis(const ConvexShape& a, const Eigen::Isometry3d& X_a,
                                  const ConvexShape& b, const Eigen::Isometry3d& X_b,
                                  const std::vector<Eigen::Vector3d>& hints) {
  AxisSeparation best;
  const auto try_axis = [&](const Eigen::Vector3d& u) {
    if (!(u.squaredNorm() > 0)) return;
    for (const Eigen::Vector3d& axis :
         {Eigen::Vector3d(u.normalized()), Eigen::Vector3d(-u.normalized())}) {
      const AxisSeparation candidate = SeparationAlong(a, X_a, b, X_b, axis);
      if (candidate.separation > best.separation) best = candidate;
    }
  };
  for (const Eigen::Vector3d& hint : hints) try_axis(hint);
  try_axis(X_a.translation() - X_b.translation());
  for (int i = 0; i < 3; ++i) try_axis(Eigen::Vector3d::Unit(i));
  for (const auto& [shape, X] : {std::pair(&a, &X_a), std::pair(&b, &X_b)}) {
    const PolyhedralShape* polyhedron = shape->AsPolyhedron();
    if (polyhedron == nullptr) continue;
    for (const Eigen::Vector3d& n : polyhedron->hull().normals) try_axis(X->linear() * n);
  }
  return best;
}

double PenetrationDepth(const ConvexShape& a, const Eigen::Isometry3d& X_a, const ConvexShape& b,
                        const Eigen::Isometry3d& X_b, double length_scale) {
  ECPSIM_DEMAND(length_scale > 0);
  ECPSIM_DEMAND(!a.IsHalfSpace() && !b.IsHalfSpace());
  const Eigen::Vector3d origin = X_a.translation();
  const PosedShape sa{&a, X_a.linear() / length_scale, Eigen::Vector3d::Zero()};
  const PosedShape sb{&b, X_b.linear() / length_scale, (X_b.translation() - origin) / length_scale};
  const ccd_t ccd = CcdQuery();
  ccd_real_t depth = 0;
  ccd_vec3_t direction, position;
  // 0: they overlap and depth is set; −1: apart; −2: out of memory, which no caller can recover
  const int status = ccdGJKPenetration(&sa, &sb, &ccd, &depth, &direction, &position);
  ECPSIM_DEMAND(status != -2);
  if (status != 0) return 0;
  return std::max(0.0, static_cast<double>(depth)) * length_scale;
}

bool WithinDistance(const ConvexShape& a, const Eigen::Isometry3d& X_a, const ConvexShape& b,
                    const Eigen::Isometry3d& X_b, double distance, double length_scale) {
  ECPSIM_DEMAND(length_scale > 0 && distance >= 0);
  ECPSIM_DEMAND(!a.IsHalfSpace() && !b.IsHalfSpace());
  if (!std::isfinite(distance)) return true;
  const Eigen::Vector3d origin = X_a.translation();
  const PosedShape sa{&a, X_a.linear() / length_scale, Eigen::Vector3d::Zero(),
                      distance / length_scale};
  const PosedShape sb{&b, X_b.linear() / length_scale, (X_b.translation() - origin) / length_scale};
  const ccd_t ccd = CcdQuery();
  return ccdGJKIntersect(&sa, &sb, &ccd) != 0;
}

}  // namespace ecpsim::geometry
