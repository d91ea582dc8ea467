#pragma once
// The one home of rotation math: skew matrices, the SO(3) exponential map, its inverse and its
// left Jacobian, roll/pitch/yaw, and the quaternion update used by the time stepper.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ecpsim::engine {

/// [w]×, so that Skew(w) * x = w × x.
Eigen::Matrix3d Skew(const Eigen::Vector3d& w);

/// Exp(φ): rotation by |φ| radians about φ/|φ| (Rodrigues; exact near φ = 0).
Eigen::Matrix3d ExpMap(const Eigen::Vector3d& phi);

/// The unit quaternion of ExpMap(φ).
Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& phi);

/// Log(q): the rotation vector φ with |φ| in [0, π] and QuaternionExp(φ) = ±q, the shortest arc
/// (q and −q are one rotation). At |φ| = π both directions are the same rotation; the one returned
/// is then decided by round-off, so callers refuse turns that close to π. `q` need not be
/// normalized (the angle is taken from the ratio of its parts); it must be finite and non-zero.
Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q);

/// R = Rz(yaw) · Ry(pitch) · Rx(roll) from [roll, pitch, yaw] in radians: rotate about the fixed
/// world x axis, then world y, then world z.
Eigen::Quaterniond RpyToQuaternion(const Eigen::Vector3d& rpy);

/// Left Jacobian J_l(φ) of SO(3): Exp(φ + δ) = Exp(J_l(φ) δ) Exp(φ) to first order in δ, so
/// ∂/∂φ (Exp(φ) x) = −[Exp(φ) x]× J_l(φ).
Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi);

/// Orientation after a step: Q⁺ = Exp(h ω) ⊗ Q with ω the world-frame angular velocity. The
/// exponential map keeps |Q⁺| = 1 (trap 3 of FORMULATION.md); the result is renormalized to clean
/// round-off.
Eigen::Quaterniond IntegrateOrientation(const Eigen::Quaterniond& Q, const Eigen::Vector3d& w,
                                        double h);

}  // namespace ecpsim::engine
