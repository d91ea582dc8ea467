#include "engine/mncp/body_step.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Cholesky>

#include "engine/loads.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// free-flight ω⁺ by Newton: quadratic convergence from the explicit estimate takes 2–4
// iterations for |hω| ≲ 1; fast tumbles (|hω| ~ 10) need damped steps, hence the margin
constexpr int kFreeFlightIterations = 50;
constexpr double kFreeFlightTolerance = 1e-15;  // × (|I_w ω| + |τ h|), round-off level

FreeFlight SolveFreeFlight(const BodyProblem& problem) {
  // I_w (ω⁺ − ω) + h ω⁺ × I_w ω⁺ = p_ext,τ by Newton from the explicit estimate; the solution
  // has ‖ω⁺‖_I ≤ ‖ω + I_w⁻¹ p_ext,τ‖_I, so damped steps that shrink the residual reach it
  const Vector3d tau = problem.p_ext.tail<3>();
  Vector3d w = problem.w + problem.inertia_world.ldlt().solve(tau);
  Vector3d r = GyroscopicResidual(problem, w) - tau;
  const double scale = (problem.inertia_world * problem.w).norm() + tau.norm();
  for (int i = 0; i < kFreeFlightIterations && r.norm() > kFreeFlightTolerance * scale; ++i) {
    const Vector3d step = GyroscopicJacobian(problem, w).partialPivLu().solve(-r);
    // halve the step until the residual shrinks; none that does: round-off level reached
    bool improved = false;
    for (double alpha = 1; alpha > 1e-9 && !improved; alpha /= 2) {
      const Vector3d trial_r = GyroscopicResidual(problem, w + alpha * step) - tau;
      if (trial_r.norm() < r.norm()) {
        w += alpha * step;
        r = trial_r;
        improved = true;
      }
    }
    if (!improved) break;
  }
  return {problem.v + problem.p_ext.head<3>() / problem.mass, w};
}

}  // namespace

// The angular Newton–Euler row without contact: I_w (ω⁺ − ω) + h ω⁺ × I_w ω⁺ (implicit
// gyroscopic impulse, engine/README.md), and its derivative in ω⁺
Vector3d GyroscopicResidual(const BodyProblem& problem, const Vector3d& w) {
  return problem.inertia_world * (w - problem.w) + problem.h * w.cross(problem.inertia_world * w);
}

Matrix3d GyroscopicJacobian(const BodyProblem& problem, const Vector3d& w) {
  const Matrix3d& I = problem.inertia_world;
  return I + problem.h * (Skew(w) * I - Skew(I * w));
}

BodyProblem StartOfStep(const Scene& scene, int body, const BodyState& state, double t, double h) {
  const Body& model = scene.bodies[body];
  BodyProblem p;
  p.h = h;
  p.mass = model.mass;
  p.R = state.Q_WB.toRotationMatrix();
  p.inertia_world = p.R * model.inertia * p.R.transpose();
  p.c = state.p_WB;
  p.v = state.v_WB;
  p.w = state.w_WB;
  p.p_ext = AppliedImpulse(scene.loads, scene.impulses, body, t, h, p.R);
  p.p_gravity = h * model.mass * scene.gravity;
  p.p_ext.head<3>() += p.p_gravity;
  p.free = SolveFreeFlight(p);
  return p;
}

bool FreeFlightIsFinite(const BodyProblem& problem, std::vector<FailedAttempt>& tried) {
  const FreeFlight& free = problem.free;
  // a finite but huge ω still overflows the rotation angle h|ω| inside Exp, whose terms are
  // finite exactly where θ² = |h ω|² is (R = I + a K + b K², |a| ≤ 1, |b| ≤ 2/θ², |K²| ≤ θ²)
  if (free.v.allFinite() && free.w.allFinite() &&
      std::isfinite((problem.h * free.w).squaredNorm())) {
    return true;
  }
  tried.push_back({"free flight", problem.h,
                   fmt::format("non-finite velocities (|ω| = {:.3g} rad/s)", problem.w.norm())});
  return false;
}

EndPose PoseAfterStep(const BodyProblem& problem, const Vector3d& v, const Vector3d& w) {
  return PoseAfterStep(problem.c, problem.R, problem.h, v, w);
}

EndPose PoseAfterStep(const Vector3d& c, const Matrix3d& R, double h, const Vector3d& v,
                      const Vector3d& w) {
  return {c + h * v, ExpMap(h * w) * R};
}

StepMotion AddBodyRows(const BodyProblem& problem, int column, const Eigen::VectorXd& z,
                       Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  StepMotion m;
  m.v = z.segment<3>(column);
  m.w = z.segment<3>(column + 3);
  m.column = column;
  m.end = PoseAfterStep(problem, m.v, m.w);
  // Newton–Euler with impulses (paper eq. discrete_NE), contact terms added per contact
  F.segment<3>(column) = problem.mass * (m.v - problem.v) - problem.p_ext.head<3>();
  F.segment<3>(column + 3) = GyroscopicResidual(problem, m.w) - problem.p_ext.tail<3>();
  if (J) {
    J->block<3, 3>(column, column) = problem.mass * Matrix3d::Identity();
    J->block<3, 3>(column + 3, column + 3) = GyroscopicJacobian(problem, m.w);
    // rotation-rate derivatives of the end pose (left Jacobians of Exp at ±hω)
    m.Jl_plus = LeftJacobian(problem.h * m.w);
    m.Rt_Jl_minus = Matrix3d(problem.R.transpose() * LeftJacobian(-problem.h * m.w));
  }
  return m;
}

double StepEnergyGain(const BodyProblem& problem, const Vector3d& v, const Vector3d& w) {
  const EndPose end = PoseAfterStep(problem, v, w);
  const Matrix3d inertia_end =
      end.R * problem.R.transpose() * problem.inertia_world * problem.R * end.R.transpose();
  const double kinetic_start = 0.5 * problem.mass * problem.v.squaredNorm() +
                               0.5 * problem.w.dot(problem.inertia_world * problem.w);
  const double kinetic_end = 0.5 * problem.mass * v.squaredNorm() + 0.5 * w.dot(inertia_end * w);
  const double potential_change = -problem.p_gravity.dot(v);
  const double loads_work =
      (problem.p_ext.head<3>() - problem.p_gravity).dot(0.5 * (problem.v + v)) +
      problem.p_ext.tail<3>().dot(0.5 * (problem.w + w));
  return kinetic_end - kinetic_start + potential_change - loads_work;
}

}  // namespace ecpsim::engine
