#pragma once
// The MNCP's convergence measure: its rows scaled to each body's own units, with the round-off
// that world coordinates carry taken out (engine/README.md, "Convergence is relative to the
// body's own scales").

#include <Eigen/Core>

#include "engine/mncp/mncp_layout.h"

namespace ecpsim::engine {

/// What the convergence measure measures lengths against (see MncpResidual).
struct ResidualUnits {
  double length;       // m: the body's length L (radius of gyration)
  double tolerance;    // the solver's tolerance on the measure (dimensionless)
  double coordinates;  // m: the largest |coordinate| of the body's centre of mass
};

/// Rows computed from world coordinates (y = R⁺ᵀ(a1 − c⁺) and the like: a rotation, two
/// differences, then the Newton solve's own error) are not asked to be more precise than this
/// many ulps of the largest coordinate involved — the ECPs' and the centre of mass's;
/// 1.4e-14 m on a body 1 m from the origin.
inline constexpr double kCoordinateRoundOffUlps = 64;

/// The MNCP's convergence measure: McpResidual of the scaled problem (each row in its body's own
/// unit, `row_scale` and `var_scale` from mncp_scaling.h), so it is dimensionless and means the
/// same for a millimetre and a kilometre body. Rows computed from world coordinates (a1 − a2 −
/// sN, the hull and obstacle constraints, the gap s, the moment r × p and the slip ω × r, with
/// r = a1 − c⁺) carry round-off of ≈ kCoordinateRoundOffUlps · ε · |x|, so a length below that
/// divided by the tolerance is not resolved: for a body far from the origin the measure is
/// relative to its coordinates instead of its length L. (The gap's tolerance, tolerance × L,
/// is a velocity error tolerance × L / h: negligible at any step a scene needs — 2e-8 m/s on a
/// 0.2 m body at h = 1e-5 s — but at h = 1e-10 s a sliding box's contact chatters by it.)
double MncpResidual(const MncpLayout& layout, const Eigen::VectorXd& z, const Eigen::VectorXd& F,
                    const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale,
                    const ResidualUnits& units);

/// MncpResidual's parts, shared with the island measure (island_mncp.h): the largest scaled row
/// error seen so far over rows added one at a time (an equation row i < num_free counts
/// |F̃_i| / divisor, a complementarity row |min(z̃_i, F̃_i / divisor)|; non-finite: ∞).
class ScaledRowResidual {
 public:
  /// The vectors are referenced, not copied: they must outlive this object.
  ScaledRowResidual(int num_free, const Eigen::VectorXd& z, const Eigen::VectorXd& F,
                    const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale);
  void AddRow(int i, double divisor);
  /// The rows of one contact block, those that carry world-coordinate round-off (see
  /// MncpResidual) divided by `factor` ≥ 1.
  void AddContact(const MncpLayout::Contact& L, double factor);
  double value() const { return value_; }

 private:
  int num_free_;
  const Eigen::VectorXd& z_;
  const Eigen::VectorXd& F_;
  const Eigen::VectorXd& row_scale_;
  const Eigen::VectorXd& var_scale_;
  double value_ = 0;
};

/// m: the length below which a contact's rows in metres are not resolved (MncpResidual): the
/// tolerance's share of kCoordinateRoundOffUlps ulps of the largest of |a1|, |a2|, |s| and
/// `coordinates` (the largest |coordinate| of the centres of mass involved).
double ContactRoundOffLength(const MncpLayout::Contact& L, const Eigen::VectorXd& z,
                             double coordinates, double tolerance);

}  // namespace ecpsim::engine
