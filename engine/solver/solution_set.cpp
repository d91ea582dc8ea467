#include "engine/solver/solution_set.h"

#include <algorithm>
#include <limits>
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

// what a solution's unknown i keeps as it moves along the set
enum class Hold {
  kRow,      // F̃_i = 0: a free row, or an active pair
  kUnknown,  // x_i = 0: an inactive pair
  kBoth,     // both: a degenerate pair
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

}  // namespace

MatrixXd SolutionSetDirections(const MatrixXd& J, const VectorXd& z, const VectorXd& F,
                               int num_free, const VectorXd& row_scale, const VectorXd& var_scale,
                               double tolerance) {
  const int n = static_cast<int>(z.size());
  std::vector<Hold> holds(n);
  int rows = n;
  for (int i = 0; i < n; ++i) {
    holds[i] = HoldOf(i, z[i] / var_scale[i], row_scale[i] * F[i], num_free, tolerance);
    if (holds[i] == Hold::kBoth) ++rows;
  }
  MatrixXd A = MatrixXd::Zero(rows, n);
  for (int i = 0, extra = n; i < n; ++i) {
    if (holds[i] != Hold::kUnknown)
      A.row(i) = row_scale[i] * J.row(i).cwiseProduct(var_scale.transpose());
    if (holds[i] == Hold::kUnknown) A(i, i) = 1;
    if (holds[i] == Hold::kBoth) A(extra++, i) = 1;
  }
  // the kernel by a fully pivoted LU (a few times cheaper than an SVD), made orthonormal
  Eigen::FullPivLU<MatrixXd> lu(A);
  lu.setThreshold(kMinimumNormRankTolerance);
  if (lu.rank() == n) return MatrixXd(n, 0);
  const MatrixXd kernel = lu.kernel();
  return Eigen::HouseholderQR<MatrixXd>(kernel).householderQ() *
         MatrixXd::Identity(n, kernel.cols());
}

SelectionResult SelectLeastEnergySolution(const McpFunction& f, int num_free,
                                          const VectorXd& row_scale, const VectorXd& var_scale,
                                          const EnergyResiduals& energy, VectorXd& z,
                                          const McpOptions& options, McpWorkspace& workspace) {
  SelectionResult result;
  const int n = static_cast<int>(z.size());
  // a solution with what the steps need there: F and J, the set's directions N, E's residuals
  struct Point {
    VectorXd z, F, r;
    MatrixXd J, N, R;
    double energy = 0;
  };
  // N at a point whose z, F and J are known
  const auto directions = [&](Point& p) {
    p.N = SolutionSetDirections(p.J, p.z, p.F, num_free, row_scale, var_scale, options.tolerance);
  };
  Point at{z, VectorXd(n), {}, {}, {}, {}, 0};
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
  while (at.N.cols() > 0 && result.steps < kMaxSelectionSteps) {
    const MatrixXd R_x = at.R * var_scale.asDiagonal();
    // (directions E barely sees, such as an unloaded contact's, are left where they are: the
    // decomposition's rank is set as the minimum-norm steps set theirs)
    Eigen::CompleteOrthogonalDecomposition<MatrixXd> gauss_newton;
    gauss_newton.setThreshold(kMinimumNormRankTolerance);
    gauss_newton.compute(R_x * at.N);
    const VectorXd dx = at.N * gauss_newton.solve(-at.r);
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
