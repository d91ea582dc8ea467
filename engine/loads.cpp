#include "engine/loads.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

#include <fmt/format.h>
#include <muParser.h>
#include <Eigen/Geometry>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

// an impulse's instant within this fraction of a step before a step boundary belongs to the step
// that starts there: `time` and the steps' t carry round-off (1e-16 relative each), far below it
constexpr double kInstantSnap = 1e-9;

}  // namespace

// the parser keeps a pointer to `t`, so the pair lives at a fixed address behind a shared_ptr;
// copies share it (a scene copied for each of several threads, the Python module's
// Simulations), so an evaluation holds the mutex: setting t and Eval() are one step
struct TimeFunction::Compiled {
  std::unique_ptr<mu::Parser> parser;  // null for a constant
  std::mutex mutex;                    // guards t and the parser's evaluation buffers
  double t = 0;
  double constant = 0;
};

TimeFunction::TimeFunction(const std::string& expression, const std::string& where)
    : expression_(expression), where_(where), compiled_(std::make_shared<Compiled>()) {
  compiled_->parser = std::make_unique<mu::Parser>();
  mu::Parser& parser = *compiled_->parser;
  try {
    parser.DefineVar("t", &compiled_->t);
    parser.DefineConst("pi", M_PI);
    parser.SetExpr(expression);
    // evaluating once forces the parse, so syntax errors and unknown variables surface here
    compiled_->t = 0;
    parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(
        fmt::format("{} = \"{}\": {}; expected an expression of t (seconds) using "
                    "numbers, pi and muparser's functions (sin, cos, exp, ...)",
                    where, expression, e.GetMsg()));
  }
  // "1, 2" parses as two results; a load component is one number
  if (parser.GetNumResults() != 1) {
    throw InputError(
        fmt::format("{} = \"{}\": {} comma-separated results; expected one "
                    "expression of t",
                    where, expression, parser.GetNumResults()));
  }
}

TimeFunction::TimeFunction(double value)
    : expression_(fmt::format("{}", value)), compiled_(std::make_shared<Compiled>()) {
  if (!std::isfinite(value)) {
    throw InputError(fmt::format("constant load value {}: expected a finite number", value));
  }
  // a constant needs no parser (Load default-constructs three of them)
  compiled_->constant = value;
}

TimeFunction::~TimeFunction() = default;
TimeFunction::TimeFunction(const TimeFunction&) = default;
TimeFunction& TimeFunction::operator=(const TimeFunction&) = default;

TimeFunction TimeFunction::Recompiled() const {
  return compiled_->parser ? TimeFunction(expression_, where_)
                           : TimeFunction(compiled_->constant);
}

double TimeFunction::operator()(double t) const {
  if (!compiled_->parser) {
    return compiled_->constant;
  }
  double value = 0;
  try {
    const std::lock_guard<std::mutex> lock(compiled_->mutex);
    compiled_->t = t;
    value = compiled_->parser->Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(
        fmt::format("{} = \"{}\" at t = {} s: {}", where_, expression_, t, e.GetMsg()));
  }
  if (!std::isfinite(value)) {
    throw InputError(
        fmt::format("{} = \"{}\" at t = {} s evaluates to {}; expected a finite "
                    "value",
                    where_, expression_, t, value));
  }
  return value;
}

Eigen::Matrix<double, 6, 1> AppliedImpulse(const std::vector<Load>& loads,
                                           const std::vector<Impulse>& impulses, int body, double t,
                                           double h, const Eigen::Matrix3d& R_WB) {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();

  // loads are sampled at the start of their active part of the step and held over it (explicit,
  // like p_app^u), for the time the step overlaps their window: a window edge that falls on a
  // step edge up to the round-off of t gives a sliver of impulse, not a whole step more or less
  const double t_end = t + h;
  for (const Load& load : loads) {
    if (load.body != body) continue;
    const double from = std::max(t, load.start);
    const double overlap = std::min(t_end, load.end) - from;
    if (!(overlap > 0)) continue;
    const Eigen::Vector3d value(load.x(from), load.y(from), load.z(from));
    const Eigen::Vector3d impulse = overlap * value;
    if (load.kind == Load::Kind::kTorque) {
      angular += impulse;
      continue;
    }
    linear += impulse;
    if (load.at_point) {
      angular += (R_WB * load.point_B).cross(impulse);
    }
  }

  // the steps of length h tile time as [k h, (k + 1) h): this step is k = round(t / h) (t carries
  // round-off), and an instant belongs to step floor(time / h), so each impulse lands exactly once
  // and an instant on a step boundary (0.5 s with h = 0.01 s) lands in the step that starts there
  const double step = std::round(t / h);
  for (const Impulse& impulse : impulses) {
    if (impulse.body != body || std::floor(impulse.time / h + kInstantSnap) != step) {
      continue;
    }
    linear += impulse.linear;
    angular += impulse.angular;
    if (impulse.at_point) {
      angular += (R_WB * impulse.point_B).cross(impulse.linear);
    }
  }

  Eigen::Matrix<double, 6, 1> result;
  result << linear, angular;
  return result;
}

}  // namespace ecpsim::engine
