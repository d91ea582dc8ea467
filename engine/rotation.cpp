#include "engine/rotation.h"

#include <cmath>

namespace ecpsim::engine {
namespace {

// below this angle the closed forms lose digits to cancellation; the Taylor series are exact to
// round-off there (next terms are O(θ⁴) ≈ 1e-24)
constexpr double kSmallAngle = 1e-6;  // rad

}  // namespace

Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d s;
  s << 0, -w.z(), w.y(),  //
      w.z(), 0, -w.x(),   //
      -w.y(), w.x(), 0;
  return s;
}

Eigen::Matrix3d ExpMap(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = Skew(phi);
  double a, b;  // R = I + a K + b K²
  if (theta < kSmallAngle) {
    a = 1 - theta * theta / 6;
    b = 0.5 - theta * theta / 24;
  } else {
    a = std::sin(theta) / theta;
    b = (1 - std::cos(theta)) / (theta * theta);
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const double half = 0.5 * theta;
  // sin(θ/2)/θ, with its series near 0
  const double s = theta < kSmallAngle ? 0.5 - theta * theta / 48 : std::sin(half) / theta;
  return Eigen::Quaterniond(std::cos(half), s * phi.x(), s * phi.y(), s * phi.z());
}

Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q) {
  // q and −q are one rotation: the half with w ≥ 0 is the shortest arc
  const double sign = q.w() < 0 ? -1.0 : 1.0;
  const Eigen::Vector3d u = sign * q.vec();
  const double s = u.norm();
  if (s == 0) return Eigen::Vector3d::Zero();
  // θ = 2 atan2(|u|, w) keeps every digit at any angle (acos(w) loses half of them near 0 and
  // π), and atan2(s, w) / s has no cancellation as s → 0
  return (2 * std::atan2(s, sign * q.w()) / s) * u;
}

Eigen::Quaterniond RpyToQuaternion(const Eigen::Vector3d& rpy) {
  return Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX());
}

Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = Skew(phi);
  double a, b;  // J_l = I + a K + b K²
  if (theta < kSmallAngle) {
    a = 0.5 - theta * theta / 24;
    b = 1.0 / 6 - theta * theta / 120;
  } else {
    a = (1 - std::cos(theta)) / (theta * theta);
    b = (theta - std::sin(theta)) / (theta * theta * theta);
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

Eigen::Quaterniond IntegrateOrientation(const Eigen::Quaterniond& Q, const Eigen::Vector3d& w,
                                        double h) {
  Eigen::Quaterniond next = QuaternionExp(h * w) * Q;
  next.normalize();
  return next;
}

}  // namespace ecpsim::engine
