#include "engine/mncp/contact_frame.h"

#include <algorithm>

#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// |N| is 1 at a solution (a unit face normal, or a convex combination of unit normals ≥ cos of
// half the dihedral angle); the floor only keeps intermediate Newton iterates finite
constexpr double kMinNormalLength = 1e-12;

}  // namespace

ContactFrame MakeContactFrame(const Vector3d& N, const Vector3d& tangent_reference) {
  ContactFrame frame;
  frame.n = N / std::max(N.norm(), kMinNormalLength);
  const Vector3d u = tangent_reference - frame.n * frame.n.dot(tangent_reference);
  frame.t = u.normalized();
  frame.o = frame.n.cross(frame.t);
  return frame;
}

FrameDerivatives ContactFrameDerivatives(const Vector3d& N, const ContactFrame& frame,
                                         const Vector3d& e) {
  const double length = std::max(N.norm(), kMinNormalLength);
  const Vector3d& n = frame.n;
  const Vector3d& t = frame.t;
  const Vector3d u = e - n * n.dot(e);
  const Matrix3d dn_dN = (Matrix3d::Identity() - n * n.transpose()) / length;
  const Matrix3d du_dn = -(n.dot(e) * Matrix3d::Identity() + n * e.transpose());
  const Matrix3d dt_du = (Matrix3d::Identity() - t * t.transpose()) / u.norm();
  const Matrix3d dt_dn = dt_du * du_dn;
  const Matrix3d do_dn = -Skew(t) + Skew(n) * dt_dn;
  return {dn_dN, dt_dn * dn_dN, do_dn * dn_dN};
}

}  // namespace ecpsim::engine
