#include "engine/solver/solution_set.h"

#include <algorithm>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/LU>
#include <Eigen/QR>

namespace ecpsim::engine {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// E's round-off relative to E: a sum of squares' few ulps
constexpr double kEnergyRoundOff = 64 * std::numeric_limits<double>::epsilon();
// the secant's step is tried where it differs from the step taken by more than this fraction
constexpr double kSecantChange = 0.1;
// a degenerate pair's hold is let go where its multiplier exceeds this fraction of E's gradient
// (scaled unknowns): far above the multipliers' round-off
constexpr double kReleaseRel = 1e-9;
// a Gauss–Newton step that a let-go pair makes longer than this (scaled unknowns: a hundred of
// their own scales) runs along a direction the energy barely sees, and the pair stays held; at a
// gripper's pad edges such steps ran to 1e4 … 2e11, and no landing follows them
constexpr double kMaxReleasedStep = 100;

// what a solution's unknown i keeps as it moves along the set
enum class Hold {
  kRow,      // F̃_i = 0: a free row, or an active pair
  kUnknown,  // x_i = 0: an inactive pair
  kBoth,     // both: a degenerate pair
  kTied,     // x_i as it is, with the unknown it is tied to; its row is left out
};

Hold HoldOf(int i, double x, double f, int num_free, double tolerance) {
  if (i < num_free || x > tolerance) return Hold::kRow;
  return f > tolerance ? Hold::kUnknown : Hold::kBoth;
}

double Measure(const McpFunction& f, int num_free, const VectorXd& row_scale,
               const VectorXd& var_scale, const McpOptions& options, const VectorXd& z, VectorXd& F,
               MatrixXd& J) {
  J.setZero(z.size(), z.size());
  f(z, &F, &J);
  return options.measure ? options.measure(z, F)
                         : McpResidual(z, F, num_free, row_scale, var_scale);
}

double Energy(const EnergyResiduals& energy, const VectorXd& z, VectorXd& r, MatrixXd* R) {
  energy(z, &r, R);
  return 0.5 * r.squaredNorm();
}

// The rows a solution keeps as it moves along the set, on the unknowns that move: the kernel of
// `A` is the set's directions in those unknowns (the others' entries 0)
struct HeldRows {
  std::vector<Hold> holds;  // per unknown
  std::vector<int> rows;    // the held rows (unknowns' indices) ...
  std::vector<int> moving;  // ... and the unknowns that move
  MatrixXd A;               // rows × moving, scaled (a tied row divided by its largest entry)
  VectorXd row_factor;      // per held row: what row i of J is multiplied by in A
};

// A degenerate pair let go on one side for one step: its unknown moves (x_i ≥ 0 with F̃_i = 0
// held), or its row does (F̃_i ≥ 0 with x_i = 0 held)
struct Release {
  int unknown;
  bool moves;
};

// the rows z holds, with `releases` let go and `ties` applied (SolutionSetDirections)
HeldRows MakeHeldRows(const MatrixXd& J, const VectorXd& z, const VectorXd& F, int num_free,
                      const VectorXd& row_scale, const VectorXd& var_scale, double tolerance,
                      const std::vector<int>& ties, const std::vector<Release>& releases) {
  const int n = static_cast<int>(z.size());
  HeldRows held;
  std::vector<Hold>& holds = held.holds;
  holds.resize(n);
  for (int i = 0; i < n; ++i)
    holds[i] = HoldOf(i, z[i] / var_scale[i], row_scale[i] * F[i], num_free, tolerance);
  for (const Release& release : releases)
    holds[release.unknown] = release.moves ? Hold::kRow : Hold::kUnknown;
  // an unknown tied to one held at 0 is held with it, and its row is left out: what it keeps is
  // kept to second order, which J does not see
  for (int i = 0; i < static_cast<int>(ties.size()); ++i)
    if (ties[i] >= 0 && holds[ties[i]] != Hold::kRow) holds[i] = Hold::kTied;
  // an unknown held at 0 (inactive or degenerate) moves in no direction: the kernel is that of
  // the held rows on the other unknowns (the moving ones), the held unknowns' entries 0. Half an
  // island's unknowns are often held so (unloaded contacts, faces out of the ECP's window), and
  // the LU's cost goes with the cube of what is left
  for (int i = 0; i < n; ++i) {
    if (holds[i] == Hold::kRow || holds[i] == Hold::kBoth) held.rows.push_back(i);
    if (holds[i] == Hold::kRow) held.moving.push_back(i);
  }
  const auto num_rows = static_cast<Eigen::Index>(held.rows.size());
  const auto num_moving = static_cast<Eigen::Index>(held.moving.size());
  held.A.resize(num_rows, num_moving);
  held.row_factor.resize(num_rows);
  for (Eigen::Index r = 0; r < num_rows; ++r) {
    const int i = held.rows[r];
    for (Eigen::Index c = 0; c < num_moving; ++c)
      held.A(r, c) = row_scale[i] * J(i, held.moving[c]) * var_scale[held.moving[c]];
    // a row tied to an unknown that moves (a loaded contact's friction row) on its own scale,
    // which leaves the kernel as it is: its entries go with the contact's state (e² μ p_n on the
    // slip, σ on the impulse), 1e-6 of the others' under a light load and 1e14 with a σ that
    // drifted, and a rank threshold set by the largest row would drop it, or every other row.
    // The other rows are in the problem's own units, where a tiny entry is round-off of a zero
    // one, which divided up would hold what does not hold
    const double largest = num_moving > 0 ? held.A.row(r).cwiseAbs().maxCoeff() : 0;
    const bool own_scale = !ties.empty() && ties[i] >= 0 && largest > 0;
    held.row_factor[r] = own_scale ? row_scale[i] / largest : row_scale[i];
    if (own_scale) held.A.row(r) /= largest;
  }
  return held;
}

// the kernel of the held rows (orthonormal columns, n rows): the set's directions
MatrixXd Kernel(const HeldRows& held, int n) {
  if (held.moving.empty()) return MatrixXd(n, 0);
  // a fully pivoted LU (a few times cheaper than an SVD), its kernel made orthonormal
  Eigen::FullPivLU<MatrixXd> lu(held.A);
  lu.setThreshold(kMinimumNormRankTolerance);
  if (lu.rank() == static_cast<int>(held.moving.size())) return MatrixXd(n, 0);
  const MatrixXd kernel = lu.kernel();
  const MatrixXd basis = Eigen::HouseholderQR<MatrixXd>(kernel).householderQ() *
                         MatrixXd::Identity(kernel.rows(), kernel.cols());
  MatrixXd N = MatrixXd::Zero(n, basis.cols());
  for (size_t c = 0; c < held.moving.size(); ++c) N.row(held.moving[c]) = basis.row(c);
  return N;
}

// The degenerate pair whose hold keeps the step dx from lowering the Gauss–Newton model
// ½ ‖R_x dx + r‖² most, if any: of the held rows' KKT multipliers λ at dx (g + Aᵀ λ = 0, g the
// model's gradient), a hold whose λ exceeds `threshold` lowers the model by λ ε when let go by ε
// on its side. A pair let go is no longer degenerate in `held`
std::optional<Release> ReleasedPair(const HeldRows& held, const MatrixXd& J,
                                    const VectorXd& var_scale, const MatrixXd& R_x,
                                    const VectorXd& r, const VectorXd& dx, double threshold) {
  // (most points have no degenerate pair: no multipliers to find)
  if (std::none_of(held.holds.begin(), held.holds.end(),
                   [](Hold hold) { return hold == Hold::kBoth; }))
    return std::nullopt;
  const VectorXd g = R_x.transpose() * (R_x * dx + r);
  VectorXd g_moving(held.moving.size());
  for (size_t c = 0; c < held.moving.size(); ++c) g_moving[c] = g[held.moving[c]];
  const VectorXd lambda =
      held.rows.empty() || held.moving.empty()
          ? VectorXd::Zero(held.rows.size())
          : VectorXd(Eigen::ColPivHouseholderQR<MatrixXd>(held.A.transpose()).solve(-g_moving));
  std::optional<Release> best;
  double best_lambda = threshold;
  for (size_t row = 0; row < held.rows.size(); ++row) {
    const int i = held.rows[row];
    if (held.holds[i] != Hold::kBoth) continue;
    // the row F̃_i = 0 (let go: F̃_i > 0), and the unknown's x_i = 0 (let go: x_i > 0), whose
    // multiplier is what the held rows leave of g_i
    double lambda_x = -g[i];
    for (size_t q = 0; q < held.rows.size(); ++q)
      lambda_x -= lambda[q] * held.row_factor[q] * J(held.rows[q], i) * var_scale[i];
    for (const auto& [moves, value] : {std::pair{false, lambda[row]}, std::pair{true, lambda_x}}) {
      if (value > best_lambda) {
        best_lambda = value;
        best = Release{i, moves};
      }
    }
  }
  return best;
}

}  // namespace

MatrixXd SolutionSetDirections(const MatrixXd& J, const VectorXd& z, const VectorXd& F,
                               int num_free, const VectorXd& row_scale, const VectorXd& var_scale,
                               double tolerance, const std::vector<int>& ties) {
  return Kernel(MakeHeldRows(J, z, F, num_free, row_scale, var_scale, tolerance, ties, {}),
                static_cast<int>(z.size()));
}

SelectionResult SelectLeastEnergySolution(const McpFunction& f, int num_free,
                                          const VectorXd& row_scale, const VectorXd& var_scale,
                                          const EnergyResiduals& energy, VectorXd& z,
                                          const McpOptions& options, McpWorkspace& workspace,
                                          const std::vector<int>& ties) {
  SelectionResult result;
  const int n = static_cast<int>(z.size());
  // a solution with what the steps need there: F and J, the set's directions N, E's residuals
  struct Point {
    VectorXd z, F, r;
    MatrixXd J, N, R;
    HeldRows held;  // (N is their kernel)
    double energy = 0;
  };
  // N at a point whose z, F and J are known
  const auto directions = [&](Point& p) {
    p.held =
        MakeHeldRows(p.J, p.z, p.F, num_free, row_scale, var_scale, options.tolerance, ties, {});
    p.N = Kernel(p.held, n);
  };
  // the Gauss–Newton step of E along the set at `p` (the least-squares solution of
  // (R_x N) y = −r, dx = N y), its degenerate pairs let go one at a time where their holds keep
  // it from lowering E's model (an active set over their one-sided holds): the same least point
  // whichever side of the tolerance such a pair's unknown or row lies
  const auto gauss_newton_step = [&](const Point& p, const MatrixXd& R_x) {
    const double threshold = kReleaseRel * (R_x.transpose() * p.r).lpNorm<Eigen::Infinity>();
    std::vector<Release> releases;
    HeldRows released;
    VectorXd dx(n), held_dx;
    for (;;) {
      const HeldRows& held = releases.empty() ? p.held : released;
      const MatrixXd N = releases.empty() ? p.N : Kernel(held, n);
      dx.setZero();
      if (N.cols() > 0) {
        // (directions E barely sees, such as a σ free along the set, are left where they are:
        // the decomposition's rank is set as the minimum-norm steps set theirs)
        Eigen::CompleteOrthogonalDecomposition<MatrixXd> decomposition;
        decomposition.setThreshold(kMinimumNormRankTolerance);
        decomposition.compute(R_x * N);
        dx = N * decomposition.solve(-p.r);
      }
      // a pair let go onto a direction the energy barely sees: no landing follows such a step
      if (!releases.empty() && !(dx.lpNorm<Eigen::Infinity>() <= kMaxReleasedStep)) return held_dx;
      const std::optional<Release> next =
          ReleasedPair(held, p.J, var_scale, R_x, p.r, dx, threshold);
      if (!next) return dx;
      held_dx = dx;
      releases.push_back(*next);
      released = MakeHeldRows(p.J, p.z, p.F, num_free, row_scale, var_scale, options.tolerance,
                              ties, releases);
    }
  };
  Point at{z, VectorXd(n), {}, {}, {}, {}, {}, 0};
  if (!(Measure(f, num_free, row_scale, var_scale, options, at.z, at.F, at.J) <= options.tolerance))
    return result;
  result.converged = true;
  directions(at);
  result.directions = static_cast<int>(at.N.cols());
  result.start_energy = result.energy = at.energy = Energy(energy, at.z, at.r, &at.R);

  McpOptions land = options;
  land.minimum_norm_steps = true;
  land.stall_iterations = kNearSetStallIterations;
  // the solution at z + alpha dx (scaled), back on the set, if its E is at most `allowed`; and
  // E's slope along the set there in the direction of dx
  const auto step_to = [&](const VectorXd& dx, double alpha, double allowed, Point& trial,
                           double& slope) {
    trial.z = at.z + alpha * var_scale.cwiseProduct(dx);
    for (int i = num_free; i < n; ++i) trial.z[i] = std::max(trial.z[i], 0.0);
    if (!SolveMcp(f, num_free, row_scale, var_scale, trial.z, land, workspace).converged)
      return false;
    trial.energy = Energy(energy, trial.z, trial.r, &trial.R);
    if (!(trial.energy <= allowed)) return false;
    trial.F.resize(n);
    Measure(f, num_free, row_scale, var_scale, options, trial.z, trial.F, trial.J);
    directions(trial);
    slope = (trial.R * var_scale.asDiagonal() * trial.N)
                .transpose()
                .lazyProduct(trial.r)
                .dot(trial.N.transpose() * dx);
    return true;
  };
  Point trial, other;
  while (result.steps < kMaxSelectionSteps) {
    const MatrixXd R_x = at.R * var_scale.asDiagonal();
    const VectorXd dx = gauss_newton_step(at, R_x);
    if (!(dx.lpNorm<Eigen::Infinity>() > options.tolerance)) break;
    // as far as the nearest active pair's boundary x_i = 0
    double alpha = 1;
    for (int i = num_free; i < n; ++i) {
      const double x = at.z[i] / var_scale[i];
      if (x > options.tolerance && dx[i] < 0) alpha = std::min(alpha, x / -dx[i]);
    }
    // a step that raises E by more than its round-off is halved (near the least point E is
    // flat to round-off, and the steps are taken on the step's own size)
    const double allowed = at.energy * (1 + kEnergyRoundOff);
    double trial_slope = 0;
    bool landed = false;
    for (int k = 0; k <= kSelectionHalvings && !landed; ++k) {
      landed = step_to(dx, alpha, allowed, trial, trial_slope);
      if (!landed) alpha *= 0.5;
    }
    if (!landed) break;
    // a curved set: Gauss–Newton does not see its curvature, the secant of E's slope along the
    // step does (slopes, unlike E, keep their precision near the least point)
    const double slope = R_x.transpose().lazyProduct(at.r).dot(dx);
    if (slope < trial_slope) {
      const double secant = alpha * slope / (slope - trial_slope);
      double other_slope = 0;
      if (std::abs(secant - alpha) > kSecantChange * alpha &&
          step_to(dx, secant, allowed, other, other_slope) &&
          std::abs(other_slope) < std::abs(trial_slope)) {
        std::swap(trial, other);
      }
    }
    std::swap(at, trial);
    ++result.steps;
  }
  z = at.z;
  result.energy = at.energy;
  for (int i = num_free; i < n; ++i) {
    if (HoldOf(i, at.z[i] / var_scale[i], row_scale[i] * at.F[i], num_free, options.tolerance) ==
        Hold::kBoth)
      result.degenerate.push_back(i);
  }
  return result;
}

}  // namespace ecpsim::engine
