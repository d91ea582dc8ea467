#include "engine/complementarity_solver.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace ecpsim::engine {
namespace {

// Armijo sufficient-decrease constant and backtracking limits
constexpr double kArmijo = 1e-4;
constexpr double kBacktrack = 0.5;
constexpr double kMinStep = 1e-12;
// a Newton direction is rejected when the linear solve is this inaccurate (singular matrix, e.g.
// σ undetermined in free flight: FORMULATION.md trap 2) ...
constexpr double kLinearSolveRelTol = 1e-6;
// ... or when it is not a descent direction by this margin (cosine with −∇Ψ)
constexpr double kMinDescentCosine = 1e-8;

struct Reformulation {
  Eigen::VectorXd phi;  // Φ(x)
  Eigen::MatrixXd H;    // an element of the generalized Jacobian of Φ
};

// penalized Fischer–Burmeister φ_λ(a, b) = λ(√(a²+b²) − a − b) − (1−λ) a₊ b₊ and its derivative
void PenalizedFb(double a, double b, double lambda, double* phi, double* da, double* db) {
  const double r = std::hypot(a, b);
  *phi = lambda * (r - a - b) - (1 - lambda) * std::max(a, 0.0) * std::max(b, 0.0);
  if (r > 0) {
    *da = lambda * (a / r - 1);
    *db = lambda * (b / r - 1);
  } else {
    // at the kink any element of the generalized gradient will do; this is the (1,1)/√2 one
    *da = *db = lambda * (M_SQRT1_2 - 1);
  }
  if (a > 0 && b > 0) {
    *da -= (1 - lambda) * b;
    *db -= (1 - lambda) * a;
  }
}

class ScaledProblem {
 public:
  ScaledProblem(const McpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                const Eigen::VectorXd& var_scale, double lambda)
      : f_(f), num_free_(num_free), row_scale_(row_scale), var_scale_(var_scale), lambda_(lambda) {}

  // Φ and (optionally) its Jacobian at scaled x; F is the unscaled residual at z = var_scale ⊙ x
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* F, Reformulation* out, bool jacobian) {
    const Eigen::VectorXd z = var_scale_.cwiseProduct(x);
    f_(z, F, jacobian ? &J_ : nullptr);
    const Eigen::VectorXd Fs = row_scale_.cwiseProduct(*F);
    const int n = static_cast<int>(x.size());
    out->phi.resize(n);
    if (jacobian) out->H = row_scale_.asDiagonal() * J_ * var_scale_.asDiagonal();
    for (int i = 0; i < n; ++i) {
      if (i < num_free_) {
        out->phi[i] = Fs[i];
        continue;
      }
      double da, db;
      PenalizedFb(x[i], Fs[i], lambda_, &out->phi[i], &da, &db);
      if (jacobian) {
        out->H.row(i) *= db;
        out->H(i, i) += da;
      }
    }
  }

 private:
  const McpFunction& f_;
  int num_free_;
  Eigen::VectorXd row_scale_, var_scale_;
  double lambda_;
  Eigen::MatrixXd J_;
};

bool AllFinite(const Eigen::VectorXd& v) { return v.allFinite(); }

}  // namespace

double McpResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& F, int num_free) {
  double r = 0;
  for (int i = 0; i < z.size(); ++i) {
    const double e = i < num_free ? std::abs(F[i]) : std::abs(std::min(z[i], F[i]));
    r = std::max(r, std::isfinite(e) ? e : INFINITY);
  }
  return r;
}

McpResult SolveMcp(const McpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z,
                   const McpOptions& options) {
  const int n = static_cast<int>(z.size());
  ScaledProblem problem(f, num_free, row_scale, var_scale, options.fb_lambda);
  Eigen::VectorXd x = z.cwiseQuotient(var_scale);
  Eigen::VectorXd F(n), F_trial(n);
  Reformulation current, trial;
  problem.Evaluate(x, &F, &current, true);

  const McpMeasure measure = options.measure ? options.measure
                                             : [num_free](const Eigen::VectorXd& zz,
                                                          const Eigen::VectorXd& FF) {
                                                 return McpResidual(zz, FF, num_free);
                                               };
  McpResult result;
  result.residual = measure(z, F);
  if (!AllFinite(current.phi)) return result;
  std::deque<double> recent_merits{0.5 * current.phi.squaredNorm()};

  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    if (result.residual <= options.tolerance) {
      result.converged = true;
      return result;
    }
    result.iterations = iteration;
    const double merit = 0.5 * current.phi.squaredNorm();
    const Eigen::VectorXd gradient = current.H.transpose() * current.phi;

    // semismooth Newton direction, else Levenberg–Marquardt with μ = ‖Φ‖² (Yamashita–Fukushima:
    // fast local convergence even where solutions are not isolated), else steepest descent
    Eigen::VectorXd direction = current.H.partialPivLu().solve(-current.phi);
    const bool newton_ok =
        AllFinite(direction) &&
        (current.H * direction + current.phi).norm() <= kLinearSolveRelTol * current.phi.norm() &&
        gradient.dot(direction) <= -kMinDescentCosine * gradient.norm() * direction.norm();
    if (!newton_ok) {
      const double mu = std::max(current.phi.squaredNorm(), 1e-20);
      Eigen::MatrixXd normal = current.H.transpose() * current.H;
      normal.diagonal().array() += mu;
      direction = normal.ldlt().solve(-gradient);
      if (!AllFinite(direction) || gradient.dot(direction) >= 0) direction = -gradient;
    }

    // non-monotone Armijo backtracking on Ψ = ½‖Φ‖²
    const double reference = *std::max_element(recent_merits.begin(), recent_merits.end());
    const double slope = gradient.dot(direction);
    double step = 1;
    bool accepted = false;
    Eigen::VectorXd x_trial;
    bool trial_has_jacobian = false;
    while (step >= kMinStep) {
      x_trial = x + step * direction;
      // the full step is usually accepted: evaluate it with its Jacobian, ready for the next
      // iteration
      trial_has_jacobian = step == 1;
      problem.Evaluate(x_trial, &F_trial, &trial, trial_has_jacobian);
      const double trial_merit = 0.5 * trial.phi.squaredNorm();
      if (AllFinite(trial.phi) && trial_merit <= reference + kArmijo * step * slope) {
        accepted = true;
        break;
      }
      step *= kBacktrack;
    }
    if (!accepted) {
      // a last resort: a short steepest-descent step on the monotone merit
      direction = -gradient;
      step = 1;
      while (step >= kMinStep) {
        x_trial = x + step * direction;
        trial_has_jacobian = false;
        problem.Evaluate(x_trial, &F_trial, &trial, false);
        if (AllFinite(trial.phi) && 0.5 * trial.phi.squaredNorm() < merit) {
          accepted = true;
          break;
        }
        step *= kBacktrack;
      }
    }
    if (!accepted) break;  // stalled: report unconverged at the last finite iterate

    x = x_trial;
    if (trial_has_jacobian) {
      std::swap(current, trial);
      std::swap(F, F_trial);
    } else {
      problem.Evaluate(x, &F, &current, true);
    }
    z = var_scale.cwiseProduct(x);
    result.residual = measure(z, F);
    recent_merits.push_back(0.5 * current.phi.squaredNorm());
    if (static_cast<int>(recent_merits.size()) > options.nonmonotone_memory)
      recent_merits.pop_front();
  }
  result.converged = result.residual <= options.tolerance;
  return result;
}

}  // namespace ecpsim::engine
