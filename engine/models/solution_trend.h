#pragma once
// The predicted start of the hull model (engine/README.md, "The predicted start"): how a contact's
// solution and its body's velocity changed over the last steps, and their quadratic
// extrapolation to the next step's end.

#include <optional>

#include <Eigen/Core>

namespace ecpsim::engine {

struct BodyState;
struct ContactState;

/// The first and second differences, over steps of length h, of a contact's point
/// [v, ω, a1, a2, s, p_n, p_t, p_o, p_r, σ] (its body's velocity in m/s and rad/s, world frame;
/// the ECPs in m; the gap s in m; the impulses in N·s and N·m·s; σ in m/s) at the steps' ends.
struct SolutionTrend {
  static constexpr int kSize = 18;
  using Point = Eigen::Matrix<double, kSize, 1, Eigen::DontAlign>;
  double h = 0;   // s, the length of the step that ended at the contact's point (0: none)
  int steps = 0;  // differences known: 0, 1 (the first) or 2 (and the second)
  Point first = Point::Zero();
  Point second = Point::Zero();
};

/// The point of `contact` (gap `s`) on `body` at the end of a step.
SolutionTrend::Point TrendPoint(const BodyState& body, const ContactState& contact, double s);

/// The trend after a step of length h from the point `before` to `after`; `last` is the trend
/// that ended at `before` (null: `before` is no solution of the same model). A difference is
/// kept only across steps of one length: after sub-steps of h/2 the next step's h starts afresh.
SolutionTrend NextTrend(const SolutionTrend* last, const SolutionTrend::Point& before,
                        const SolutionTrend::Point& after, double h);

/// Whether `trend` knows two differences over steps of length h (PredictPoint then predicts).
bool Predicts(const SolutionTrend& trend, double h);

/// The point `now` extrapolated over one more step of length h (exact for a point quadratic in
/// time), or none unless `trend` knows two differences over steps of length h.
std::optional<SolutionTrend::Point> PredictPoint(const SolutionTrend& trend,
                                                 const SolutionTrend::Point& now, double h);

}  // namespace ecpsim::engine
