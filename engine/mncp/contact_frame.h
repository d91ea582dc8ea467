#pragma once
// A contact's frame (n, t, o) from the obstacle's normal-cone combination N, and its derivatives
// in N for the MNCP's Jacobian.

#include <Eigen/Core>

namespace ecpsim::engine {

/// The contact frame (n, t, o) from the obstacle's normal-cone combination N = Σ l_G ∇g.
struct ContactFrame {
  Eigen::Vector3d n, t, o;
};
ContactFrame MakeContactFrame(const Eigen::Vector3d& N, const Eigen::Vector3d& tangent_reference);

/// Derivatives of MakeContactFrame(N, e)'s axes with respect to N (1/m where N is a gradient).
struct FrameDerivatives {
  Eigen::Matrix3d dn_dN, dt_dN, do_dN;
};
FrameDerivatives ContactFrameDerivatives(const Eigen::Vector3d& N, const ContactFrame& frame,
                                         const Eigen::Vector3d& e);
}  // namespace ecpsim::engine
