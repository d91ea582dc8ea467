#pragma once
// Applied loads: forces and torques as expressions of time (muparser), and impulses at instants.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ecpsim::engine {

/// A scalar function of time t (seconds) compiled from an expression such as
/// "22.5*sin(2*pi*t)+22.5"; `pi` and `t` are defined. Cheap to copy (shares the compiled parser);
/// safe to evaluate from several threads (copies too: an evaluation locks the shared parser).
class TimeFunction {
 public:
  /// @throws InputError with `where` (file:line:col key) if the expression does not parse or uses
  ///         an unknown variable.
  TimeFunction(const std::string& expression, const std::string& where);
  /// A constant.
  explicit TimeFunction(double value = 0);
  ~TimeFunction();
  TimeFunction(const TimeFunction&);
  TimeFunction& operator=(const TimeFunction&);

  /// @throws InputError if the value is not finite at t (e.g. 1/(t-1) at t = 1).
  double operator()(double t) const;
  const std::string& expression() const { return expression_; }

  /// The same function with a compiled expression of its own: copies share one, whose
  /// evaluations take turns (a lock), so threads that step copies of a scene side by side each
  /// want their own.
  TimeFunction Recompiled() const;

 private:
  struct Compiled;
  std::string expression_;
  std::string where_;
  std::shared_ptr<Compiled> compiled_;
};

/// A force or torque on one body, given in world coordinates, active for t in [start, end).
struct Load {
  enum class Kind { kForce, kTorque };
  Kind kind = Kind::kForce;
  int body = 0;
  TimeFunction x, y, z;   // N or N·m, world frame
  bool at_point = false;  // force applied at `point_B` instead of the centre of mass
  Eigen::Vector3d point_B = Eigen::Vector3d::Zero();  // m, body frame (origin at the CM)
  double start = 0;                                   // s
  double end = 1e300;                                 // s
};

/// An instantaneous impulse applied at the first step whose interval contains `time`.
struct Impulse {
  int body = 0;
  double time = 0;                                    // s
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // N·s, world frame
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // N·m·s, world frame, about the CM
  bool at_point = false;                              // linear impulse applied at point_B
  Eigen::Vector3d point_B = Eigen::Vector3d::Zero();  // m, body frame
};

/// Σ over `loads` and `impulses` of body `body`'s applied impulse over the step [t, t + h): each
/// load's value at the start of its active part of the step times the time the step overlaps
/// its window [start, end) (explicit in the loads, like the paper's p_app^u), and the impulses
/// whose instant lies in the step (steps tile time as [k h, (k + 1) h), k = round(t / h)).
/// Returns (linear N·s; angular N·m·s about the CM, world frame). `R_WB` rotates body points of
/// loads applied at points.
Eigen::Matrix<double, 6, 1> AppliedImpulse(const std::vector<Load>& loads,
                                           const std::vector<Impulse>& impulses, int body, double t,
                                           double h, const Eigen::Matrix3d& R_WB);

}  // namespace ecpsim::engine
