#include "engine/models/solution_trend.h"

#include "engine/state.h"

namespace ecpsim::engine {

SolutionTrend::Point TrendPoint(const BodyState& body, const ContactState& contact, double s) {
  SolutionTrend::Point point;
  point << body.v_WB, body.w_WB, contact.a1, contact.a2, s, contact.p_n, contact.p_t, contact.p_o,
      contact.p_r, contact.sigma;
  return point;
}

SolutionTrend NextTrend(const SolutionTrend* last, const SolutionTrend::Point& before,
                        const SolutionTrend::Point& after, double h) {
  SolutionTrend trend;
  trend.h = h;
  // `before` ended a step of another length (or of another model): its impulses are not this
  // step's, and the differences start afresh
  if (last == nullptr || last->h != h) return trend;
  trend.first = after - before;
  trend.steps = 1;
  if (last->steps >= 1) {
    trend.second = trend.first - last->first;
    trend.steps = 2;
  }
  return trend;
}

bool Predicts(const SolutionTrend& trend, double h) { return trend.steps >= 2 && trend.h == h; }

std::optional<SolutionTrend::Point> PredictPoint(const SolutionTrend& trend,
                                                 const SolutionTrend::Point& now, double h) {
  if (!Predicts(trend, h)) return std::nullopt;
  // z(t + h) ≈ z + (z − z₋₁) + (z − 2 z₋₁ + z₋₂)
  return SolutionTrend::Point(now + trend.first + trend.second);
}

}  // namespace ecpsim::engine
