#pragma once
// The one home of rotation math: skew matrices, the SO(3) exponential map and its left Jacobian,
// and the quaternion update used by the time stepper.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ecpsim::engine {

/// [w]×, so that Skew(w) * x = w × x.
Eigen::Matrix3d Skew(const Eigen::Vector3d& w);

/// Exp(φ): rotation by |φ| radians about φ/|φ| (Rodrigues; exact near φ = 0).
Eigen::Matrix3d ExpMap(const Eigen::Vector3d& phi);

/// The unit quaternion of ExpMap(φ).
Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& phi);

/// Left Jacobian J_l(φ) of SO(3): Exp(φ + δ) = Exp(J_l(φ) δ) Exp(φ) to first order in δ, so
/// ∂/∂φ (Exp(φ) x) = −[Exp(φ) x]× J_l(φ).
Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi);

/// Orientation after a step: Q⁺ = Exp(h ω) ⊗ Q with ω the world-frame angular velocity. The
/// exponential map keeps |Q⁺| = 1 (trap 3 of FORMULATION.md); the result is renormalized to clean
/// round-off.
Eigen::Quaterniond IntegrateOrientation(const Eigen::Quaterniond& Q, const Eigen::Vector3d& w,
                                        double h);

}  // namespace ecpsim::engine
