#include "engine/solver/complementarity_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/OrderingMethods>
#include <Eigen/QR>

#include "engine/solver/pattern_lu.h"
#include "engine/solver/sparse_factorizations.h"

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
// the Levenberg–Marquardt damping μ = d ‖Φ‖ adapts d within these bounds by this factor
constexpr double kDampingFactor = 4;
constexpr double kMinDamping = 1e-6;
constexpr double kMaxDamping = 1e6;
// a residual that has not fallen by this fraction of its best value for
// McpOptions::stall_iterations iterations has stalled
constexpr double kStallProgress = 0.5;
// a Newton step the line search cut below this fraction is compared with a Levenberg–Marquardt
// step (see SolveMcp)
constexpr double kMinNewtonStep = 0.25;
// the constant C of quadratic convergence, r_next ≈ C r², assumed for the first Newton step
// (later ones measure it): O(1) in the scaled problem's units. Measured on the first steps of
// scenes/*.yaml that did not end their solve (medians; tails to 5 … 70): 0.04 on the hull
// desk's predicted starts, 0.08 on the T-bar's, 0.4 on the dumbbell's. A first step from a start
// above √tolerance (1e-6) is then predicted to go on, and its trial is evaluated with the
// Jacobian the next step needs instead of twice, without and then with it (the hull desk: 5 %
// fewer instructions, every trajectory bit-identical); the planar step, which a slide's first
// step solves exactly from 1e-2, forms one Jacobian more there, at 4 unknowns
constexpr double kFirstStepContraction = 1;

template <typename Matrix>
struct Reformulation {
  Eigen::VectorXd phi;  // Φ(x)
  Matrix H;             // an element of the generalized Jacobian of Φ
  // the proximal term's diagonal E in H's units (McpOptions::proximal_weight): ε on a free row,
  // ε ∂φ/∂F̃ on a complementarity row; empty without the option
  Eigen::VectorXd proximal;
};

// penalized Fischer–Burmeister φ_λ(a, b) = λ(√(a²+b²) − a − b) − (1−λ) a₊ b₊, with
// r = √(a²+b²) for its derivative
double PenalizedFb(double a, double b, double lambda, double* r) {
  *r = std::hypot(a, b);
  return lambda * (*r - a - b) - (1 - lambda) * std::max(a, 0.0) * std::max(b, 0.0);
}

// the derivative of φ_λ's smoothing with √(a²+b²+2μ²) (Jacobian smoothing, Chen–Qi–Sun: the
// value is the true φ_λ, the derivative is nonsingular where a and b are both near 0); r is
// √(a²+b²) from PenalizedFb
void PenalizedFbDerivative(double a, double b, double r, double lambda, double mu, double* da,
                           double* db) {
  const double rs = std::sqrt(r * r + 2 * mu * mu);
  if (rs > 0) {
    *da = lambda * (a / rs - 1);
    *db = lambda * (b / rs - 1);
  } else {
    // at the kink any element of the generalized gradient will do; this is the (1,1)/√2 one
    *da = *db = lambda * (M_SQRT1_2 - 1);
  }
  if (a > 0 && b > 0) {
    *da -= (1 - lambda) * b;
    *db -= (1 - lambda) * a;
  }
}

// ScaledProblem's storage, kept from call to call
template <typename Matrix>
struct ScaledStorage {
  Eigen::VectorXd z, row_factor, diagonal, fb_radius;
  Matrix J;
  bool J_zero = false;  // dense: J is n × n and zero (McpFunction's contract)
};

// J ready for the callback: dense, n × n and zero (cleared only when a previous evaluation did
// not leave it so, see FormNewtonMatrix); sparse, as the callback leaves it
void PrepareJacobian(ScaledStorage<Eigen::MatrixXd>& storage, Eigen::Index n) {
  if (!storage.J_zero || storage.J.rows() != n) storage.J.setZero(n, n);
  storage.J_zero = false;
}
void PrepareJacobian(ScaledStorage<SparseMatrix>& /*storage*/, Eigen::Index /*n*/) {}

// H = diag(row_factor) J diag(var_scale) + diag(diagonal), dense; J is cleared in the same pass,
// ready for the next evaluation (one pass over it instead of two)
void FormNewtonMatrix(ScaledStorage<Eigen::MatrixXd>& storage, const Eigen::VectorXd& row_factor,
                      const Eigen::VectorXd& var_scale, const Eigen::VectorXd& diagonal,
                      Eigen::MatrixXd& H) {
  Eigen::MatrixXd& J = storage.J;
  const Eigen::Index n = J.cols();
  H.resize(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    double* const J_col = J.col(j).data();
    double* const H_col = H.col(j).data();
    const double scale = var_scale[j];
    for (Eigen::Index i = 0; i < n; ++i) {
      H_col[i] = (scale * row_factor[i]) * J_col[i];
      J_col[i] = 0;
    }
  }
  storage.J_zero = true;
  H.diagonal() += diagonal;
}

// the same on J's pattern (the diagonal added to it where missing): the same products, entry by
// entry
void FormNewtonMatrix(ScaledStorage<SparseMatrix>& storage, const Eigen::VectorXd& row_factor,
                      const Eigen::VectorXd& var_scale, const Eigen::VectorXd& diagonal,
                      SparseMatrix& H) {
  H = storage.J;
  H.makeCompressed();
  for (Eigen::Index j = 0; j < H.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(H, j); it; ++it)
      it.valueRef() = (var_scale[j] * row_factor[it.row()]) * it.value();
  for (Eigen::Index j = 0; j < H.cols(); ++j)
    if (diagonal[j] != 0) H.coeffRef(j, j) += diagonal[j];
  H.makeCompressed();
}

template <typename Matrix>
class ScaledProblem {
 public:
  using Function = std::function<void(const Eigen::VectorXd&, Eigen::VectorXd*, Matrix*)>;
  ScaledProblem(const Function& f, int num_free, const Eigen::VectorXd& row_scale,
                const Eigen::VectorXd& var_scale, double lambda, double smoothing,
                double proximal, ScaledStorage<Matrix>& storage)
      : f_(f),
        num_free_(num_free),
        row_scale_(row_scale),
        var_scale_(var_scale),
        lambda_(lambda),
        smoothing_(smoothing),
        proximal_(proximal),
        storage_(storage) {}

  // Φ and (optionally) its Jacobian at scaled x; F is the unscaled residual at z = var_scale ⊙ x
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* F, Reformulation<Matrix>* out,
                bool jacobian) {
    // the storage's and out's members keep their storage from call to call: no allocation per
    // iterate
    Eigen::VectorXd& z = storage_.z;
    Eigen::VectorXd& radius = storage_.fb_radius;
    const int n = static_cast<int>(x.size());
    z = var_scale_.cwiseProduct(x);
    if (jacobian) PrepareJacobian(storage_, n);
    f_(z, F, jacobian ? &storage_.J : nullptr);
    out->phi.resize(n);
    radius.resize(n);
    for (int i = 0; i < n; ++i) {
      const double Fs = row_scale_[i] * (*F)[i];
      out->phi[i] = i < num_free_ ? Fs : PenalizedFb(x[i], Fs, lambda_, &radius[i]);
    }
    if (!jacobian) return;
    // H = diag(row_factor) J diag(var_scale) + diag(diagonal): row_factor is row_scale times
    // ∂φ/∂F̃ on complementarity rows, diagonal is ∂φ/∂x there, formed in one pass over J. The
    // smoothing parameter shrinks with the residual, so the Newton iteration keeps its fast
    // local convergence
    Eigen::VectorXd& row_factor = storage_.row_factor;
    Eigen::VectorXd& diagonal = storage_.diagonal;
    row_factor.resize(n);
    diagonal.setZero(n);
    row_factor.head(num_free_) = row_scale_.head(num_free_);
    const double mu = smoothing_ * out->phi.norm();
    double da, db;
    for (int i = num_free_; i < n; ++i) {
      PenalizedFbDerivative(x[i], row_scale_[i] * (*F)[i], radius[i], lambda_, mu, &da, &db);
      row_factor[i] = row_scale_[i] * db;
      diagonal[i] = da;
    }
    FormNewtonMatrix(storage_, row_factor, var_scale_, diagonal, out->H);
    if (proximal_ > 0) {
      // the scaled problem's F̃_i + ε (x_i − x_i,k), differentiated through φ as F̃ is
      out->proximal.resize(n);
      out->proximal.head(num_free_).setConstant(proximal_);
      for (int i = num_free_; i < n; ++i)
        out->proximal[i] = proximal_ * row_factor[i] / row_scale_[i];
    }
  }

 private:
  const Function& f_;
  int num_free_;
  const Eigen::VectorXd& row_scale_;
  const Eigen::VectorXd& var_scale_;
  double lambda_;
  double smoothing_;
  double proximal_;
  ScaledStorage<Matrix>& storage_;
};

bool AllFinite(const Eigen::VectorXd& v) { return v.allFinite(); }

// H d = b in the minimum-norm least-squares sense (McpOptions::minimum_norm_steps), with the
// rank decided by kMinimumNormRankTolerance; the factorization and its storage kept from call to
// call
class MinimumNormSolver {
 public:
  void Factor(const Eigen::MatrixXd& H) {
    cod_.setThreshold(kMinimumNormRankTolerance);
    cod_.compute(H);
  }
  void Solve(Eigen::VectorXd& x) {
    rhs_ = x;
    x = cod_.solve(rhs_);
  }

 private:
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
  Eigen::VectorXd rhs_;
};

// The Newton matrix's linear algebra, dense: PatternLu for the Newton direction (the elimination
// replayed on the matrix's non-zeros) and the normal matrix HᵀH for the Levenberg–Marquardt one —
// the fastest for one body's MNCP and small islands
class DenseNewtonAlgebra {
 public:
  using Matrix = Eigen::MatrixXd;
  // the largest solve whose storage is kept (WorkspaceLease): its matrices are then at most a
  // few hundred kB
  static constexpr int kMaxKeptUnknowns = 256;
  // (a dense factorization keeps nothing from solve to solve but storage)
  void BeginSolve() {}
  // the dense elimination (in `order`, McpOptions::elimination_order, when not empty), or
  // (replay) the pattern's schedule with threshold pivoting, or (minimum_norm) the complete
  // orthogonal decomposition
  void Factor(const Matrix& H, const Eigen::VectorXd* shift, bool replay, bool minimum_norm,
              const std::vector<int>& order) {
    minimum_norm_ = minimum_norm;
    const Matrix* factored = &H;
    if (shift) {
      shifted_ = H;
      shifted_.diagonal() += *shift;
      factored = &shifted_;
    }
    if (minimum_norm) {
      minimum_norm_solver_.Factor(*factored);
    } else {
      lu_.Compute(*factored, replay, order);
    }
  }
  // x ← H⁻¹ x (non-finite where H is singular), or the minimum-norm least-squares solution
  void Solve(Eigen::VectorXd& x) {
    if (minimum_norm_) {
      minimum_norm_solver_.Solve(x);
    } else {
      lu_.SolveInPlace(x);
    }
  }
  // direction = −(HᵀH + μ I)⁻¹ gradient
  static void SolveDamped(const Matrix& H, double mu, const Eigen::VectorXd& gradient,
                          Eigen::VectorXd& direction) {
    Eigen::MatrixXd normal = H.transpose() * H;
    normal.diagonal().array() += mu;
    direction = normal.ldlt().solve(-gradient);
  }

 private:
  PatternLu lu_;
  MinimumNormSolver minimum_norm_solver_;
  bool minimum_norm_ = false;
  Matrix shifted_;  // H + diag(shift)
};

// The same on a sparse H (an island's: bodies' 6 × 6 blocks coupled only through their shared
// contacts, engine/README.md "The island's linear algebra"): KLU's LU for the Newton direction,
// and the Levenberg–Marquardt direction from the augmented system, as sparse as H
// (sparse_factorizations.h). Both cost in proportion to the island for a chain of bodies.
class SparseNewtonAlgebra {
 public:
  using Matrix = SparseMatrix;
  // every solve's storage is kept: it grows with the non-zeros, not their square, and the
  // analyses kept with it are what the next solve of an island of the same pattern saves
  static constexpr int kMaxKeptUnknowns = std::numeric_limits<int>::max();
  // the analyses are kept within a solve for matrices whose non-zeros they cover, and into the
  // next only for one of the same pattern (PatternCover): the factors depend on the solve alone
  void BeginSolve() {
    lu_.BeginSolve();
    damped_.BeginSolve();
  }
  // (the sparse LU keeps its analysis per pattern anyway: `replay` changes nothing here; the
  // minimum-norm solve factors H dense: a rescue's cost, not a step's)
  void Factor(const Matrix& matrix, const Eigen::VectorXd* shift, bool /*replay*/,
              bool minimum_norm, const std::vector<int>& /*order*/) {
    const Matrix* factored = &matrix;
    if (shift) {
      shifted_ = matrix;
      for (Eigen::Index j = 0; j < shifted_.cols(); ++j) shifted_.coeffRef(j, j) += (*shift)[j];
      shifted_.makeCompressed();
      factored = &shifted_;
    }
    const Matrix& H = *factored;
    // a non-finite entry would reach the LU's pivot search, whose comparisons it defeats
    factored_ = AllFinite(H);
    minimum_norm_ = minimum_norm;
    if (!factored_) return;
    if (minimum_norm) {
      minimum_norm_solver_.Factor(Eigen::MatrixXd(H));
      return;
    }
    factored_ = lu_.Factor(H);
  }
  void Solve(Eigen::VectorXd& x) {
    if (!factored_) {
      x.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    if (minimum_norm_) {
      minimum_norm_solver_.Solve(x);
      return;
    }
    lu_.SolveInPlace(x);
  }
  void SolveDamped(const Matrix& H, double mu, const Eigen::VectorXd& gradient,
                   Eigen::VectorXd& direction) {
    damped_.Solve(H, mu, gradient, direction);
  }

 private:
  static bool AllFinite(const Matrix& H) {
    return Eigen::Map<const Eigen::VectorXd>(H.valuePtr(), H.nonZeros()).allFinite();
  }

  bool factored_ = false;
  bool minimum_norm_ = false;
  MinimumNormSolver minimum_norm_solver_;
  SparseLu lu_;
  Matrix shifted_;  // H + diag(shift)
  DampedLeastSquares damped_;
};

// the storage of one solve, kept from solve to solve (one per thread and algebra), so that a
// time step allocates nothing once its sizes have been seen
template <typename Algebra>
struct Workspace {
  using Matrix = typename Algebra::Matrix;
  ScaledStorage<Matrix> scaled;
  Eigen::VectorXd x, F, F_trial, gradient, direction, linear_residual, x_trial, x_saved, F_saved;
  Reformulation<Matrix> current, trial, saved;
  Algebra algebra;
  std::vector<double> recent_merits;
};

// a caller's storage of one algebra, and whether a solve has it
template <typename Algebra>
struct KeptWorkspace {
  std::unique_ptr<Workspace<Algebra>> workspace;
  bool in_use = false;
};

// lends `kept`'s storage to one solve of n unknowns for its lifetime; a solve nested in a
// callback's evaluation of a solve on the same storage, or one so large that its matrices should
// not stay allocated after it (a whole big hull), uses storage of its own
template <typename Algebra>
class WorkspaceLease {
 public:
  WorkspaceLease(int n, KeptWorkspace<Algebra>& kept)
      : kept_(kept), borrowed_(!kept.in_use && n <= Algebra::kMaxKeptUnknowns) {
    // (built only when used: its thirty-odd members are not free to build and destroy per solve)
    if (!borrowed_) {
      own_.emplace();
      return;
    }
    if (!kept_.workspace) kept_.workspace = std::make_unique<Workspace<Algebra>>();
    kept_.in_use = true;
  }
  ~WorkspaceLease() {
    if (borrowed_) kept_.in_use = false;
  }
  WorkspaceLease(const WorkspaceLease&) = delete;
  WorkspaceLease& operator=(const WorkspaceLease&) = delete;
  Workspace<Algebra>& Get() { return borrowed_ ? *kept_.workspace : *own_; }

 private:
  KeptWorkspace<Algebra>& kept_;
  const bool borrowed_;
  std::optional<Workspace<Algebra>> own_;
};

}  // namespace

double McpResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& F, int num_free,
                   const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale) {
  double r = 0;
  for (int i = 0; i < z.size(); ++i) {
    const double f = row_scale[i] * F[i];
    const double e = i < num_free ? std::abs(f) : std::abs(std::min(z[i] / var_scale[i], f));
    r = std::max(r, std::isfinite(e) ? e : INFINITY);
  }
  return r;
}

namespace {

// SolveMcp with the Newton matrix's linear algebra `Algebra` (dense or sparse)
template <typename Algebra>
McpResult SolveMcpWith(const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd*,
                                                typename Algebra::Matrix*)>& f,
                       int num_free, const Eigen::VectorXd& row_scale,
                       const Eigen::VectorXd& var_scale, Eigen::VectorXd& z,
                       const McpOptions& options, WorkspaceLease<Algebra>& lease,
                       const CancelFlag* cancel) {
  using Matrix = typename Algebra::Matrix;
  const int n = static_cast<int>(z.size());
  Workspace<Algebra>& w = lease.Get();
  ScaledProblem<Matrix> problem(f, num_free, row_scale, var_scale, options.fb_lambda,
                                options.jacobian_smoothing, options.proximal_weight, w.scaled);
  Eigen::VectorXd& x = w.x;
  Eigen::VectorXd& F = w.F;
  Eigen::VectorXd& F_trial = w.F_trial;
  Reformulation<Matrix>& current = w.current;
  Reformulation<Matrix>& trial = w.trial;
  x = z.cwiseQuotient(var_scale);
  const bool project = options.project_nonnegative;
  if (project) x.tail(n - num_free) = x.tail(n - num_free).cwiseMax(0.0);
  F.resize(n);
  F_trial.resize(n);

  McpResult result;
  // the measure of (z, F): the problem's own, else McpResidual of the scaled problem (no
  // std::function in between)
  auto measure = [&](const Eigen::VectorXd& zz, const Eigen::VectorXd& FF) {
    return options.measure ? options.measure(zz, FF)
                           : McpResidual(zz, FF, num_free, row_scale, var_scale);
  };
  if (options.verify_start_first) {
    // F alone decides whether the start is a solution: then no Jacobian is formed (the same F,
    // the same decision as the first iteration's below)
    problem.Evaluate(x, &F, &current, false);
    result.residual = measure(z, F);
    if (!AllFinite(current.phi)) return result;
    if (result.residual <= std::min(options.tolerance, options.start_tolerance)) {
      result.converged = true;
      return result;
    }
  }
  problem.Evaluate(x, &F, &current, true);
  result.residual = measure(z, F);
  if (!AllFinite(current.phi)) return result;
  // the last few merit values, oldest first (a handful: erasing at the front is cheap)
  std::vector<double>& recent_merits = w.recent_merits;
  recent_merits.clear();
  recent_merits.push_back(0.5 * current.phi.squaredNorm());

  Algebra& algebra = w.algebra;
  algebra.BeginSolve();
  Eigen::VectorXd& gradient = w.gradient;
  Eigen::VectorXd& direction = w.direction;
  Eigen::VectorXd& linear_residual = w.linear_residual;
  Eigen::VectorXd& x_trial = w.x_trial;
  Eigen::VectorXd& x_saved = w.x_saved;
  Eigen::VectorXd& F_saved = w.F_saved;
  Reformulation<Matrix>& saved = w.saved;
  double lm_damping = 1;  // of ‖Φ‖, the Levenberg–Marquardt damping (adapted below)
  double best_residual = result.residual;  // and the iteration that reached it (stall test)
  int best_iteration = 0;
  double previous_residual = INFINITY;  // the measure one iteration earlier
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    const double tolerance =
        iteration == 1 ? std::min(options.tolerance, options.start_tolerance) : options.tolerance;
    if (result.residual <= tolerance) {
      result.converged = true;
      return result;
    }
    ThrowIfCancelled(cancel, "the complementarity solve");
    result.iterations = iteration;
    const double merit = 0.5 * current.phi.squaredNorm();
    gradient.noalias() = current.H.transpose() * current.phi;

    // semismooth Newton direction, else Levenberg–Marquardt with μ = ‖Φ‖² (Yamashita–Fukushima:
    // fast local convergence even where solutions are not isolated), else steepest descent
    const Eigen::VectorXd* proximal = options.proximal_weight > 0 ? &current.proximal : nullptr;
    algebra.Factor(current.H, proximal, options.replay_pivots, options.minimum_norm_steps,
                   options.elimination_order);
    direction = -current.phi;
    algebra.Solve(direction);
    bool newton_ok = AllFinite(direction);
    if (newton_ok) {
      // (of the system solved: with the proximal term, (H + E) d = −Φ)
      linear_residual.noalias() = current.H * direction;
      linear_residual += current.phi;
      if (proximal) linear_residual += proximal->cwiseProduct(direction);
      newton_ok =
          linear_residual.norm() <= kLinearSolveRelTol * current.phi.norm() &&
          gradient.dot(direction) <= -kMinDescentCosine * gradient.norm() * direction.norm();
    }
    const auto lm_direction = [&](double mu) {
      algebra.SolveDamped(current.H, std::max(mu, 1e-20), gradient, direction);
      if (!AllFinite(direction) || gradient.dot(direction) >= 0) direction = -gradient;
    };
    if (!newton_ok) lm_direction(current.phi.squaredNorm());

    // non-monotone Armijo backtracking on Ψ = ½‖Φ‖²
    const double reference = *std::max_element(recent_merits.begin(), recent_merits.end());
    // the full step's Jacobian is needed only if the iteration goes on: when quadratic
    // convergence (r_next ≈ C r², C = r / r_previous² from the last step, kFirstStepContraction
    // before any) predicts a full step to end under the tolerance, the trial is evaluated
    // without it, and only computed after all if the measure says otherwise. The stop stays the
    // measure at an evaluated iterate, never the prediction
    const double contraction = previous_residual == INFINITY
                                   ? kFirstStepContraction
                                   : result.residual / (previous_residual * previous_residual);
    const bool predict_converged =
        contraction * result.residual * result.residual <= options.tolerance;
    double step = 1;
    bool accepted = false;
    bool trial_has_jacobian = false;
    const auto line_search = [&]() {
      const double slope = gradient.dot(direction);
      step = 1;
      accepted = false;
      while (step >= kMinStep) {
        x_trial = x + step * direction;
        if (project) x_trial.tail(n - num_free) = x_trial.tail(n - num_free).cwiseMax(0.0);
        // the full step is usually accepted: evaluate it with its Jacobian, ready for the next
        // iteration
        trial_has_jacobian = step == 1 && !predict_converged;
        problem.Evaluate(x_trial, &F_trial, &trial, trial_has_jacobian);
        const double trial_merit = 0.5 * trial.phi.squaredNorm();
        if (AllFinite(trial.phi) && trial_merit <= reference + kArmijo * step * slope) {
          accepted = true;
          return;
        }
        step *= kBacktrack;
      }
    };
    line_search();
    // a Newton step cut short by the line search: the Newton matrix is nearly singular along
    // some direction (an ECP free to slide along an edge while it rocks), where the full step
    // overshoots; the Levenberg–Marquardt step with the larger damping μ = ‖Φ‖ (Fan–Yuan) leaves
    // that direction alone. The better of the two trial points is kept.
    if (options.levenberg_marquardt_rescue && newton_ok && (!accepted || step < kMinNewtonStep)) {
      const bool newton_accepted = accepted;
      const double newton_merit = 0.5 * trial.phi.squaredNorm();
      const double newton_step = step;
      const bool newton_jacobian = trial_has_jacobian;
      std::swap(x_trial, x_saved);
      std::swap(F_trial, F_saved);
      std::swap(trial, saved);
      lm_direction(lm_damping * current.phi.norm());
      line_search();
      const bool lm_better =
          accepted && (!newton_accepted || 0.5 * trial.phi.squaredNorm() < newton_merit);
      // the damping adapts as in a trust region: a full Levenberg–Marquardt step that won
      // allows less damping next time, anything else asks for more
      lm_damping = lm_better && step == 1 ? std::max(lm_damping / kDampingFactor, kMinDamping)
                                          : std::min(lm_damping * kDampingFactor, kMaxDamping);
      if (!lm_better && newton_accepted) {
        std::swap(x_trial, x_saved);
        std::swap(F_trial, F_saved);
        std::swap(trial, saved);
        accepted = true;
        step = newton_step;
        trial_has_jacobian = newton_jacobian;
      }
    }
    if (!accepted) {
      // a last resort: a short steepest-descent step on the monotone merit
      direction = -gradient;
      step = 1;
      while (step >= kMinStep) {
        x_trial = x + step * direction;
        if (project) x_trial.tail(n - num_free) = x_trial.tail(n - num_free).cwiseMax(0.0);
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

    x.swap(x_trial);
    if (trial_has_jacobian) {
      std::swap(current, trial);
      std::swap(F, F_trial);
    } else {
      // F at x is the trial's: a converged x ends the solve without its Jacobian
      z = var_scale.cwiseProduct(x);
      const double residual = measure(z, F_trial);
      if (residual <= options.tolerance) {
        result.residual = residual;
        result.converged = true;
        return result;
      }
      problem.Evaluate(x, &F, &current, true);
    }
    z = var_scale.cwiseProduct(x);
    previous_residual = result.residual;
    result.residual = measure(z, F);
    recent_merits.push_back(0.5 * current.phi.squaredNorm());
    if (static_cast<int>(recent_merits.size()) > options.nonmonotone_memory)
      recent_merits.erase(recent_merits.begin());
    // a stalled solve gives up early: the caller has other guesses and smaller steps to try
    if (result.residual < best_residual * (1 - kStallProgress)) {
      best_residual = result.residual;
      best_iteration = iteration;
    } else if (options.stall_iterations > 0 &&
               iteration - best_iteration >= options.stall_iterations) {
      break;
    }
  }
  result.converged = result.residual <= options.tolerance;
  return result;
}

}  // namespace

struct McpWorkspace::Storage {
  KeptWorkspace<DenseNewtonAlgebra> dense;
  KeptWorkspace<SparseNewtonAlgebra> sparse;
};

McpWorkspace::McpWorkspace() : storage_(std::make_unique<Storage>()) {}
McpWorkspace::~McpWorkspace() = default;
McpWorkspace::McpWorkspace(McpWorkspace&&) noexcept = default;
McpWorkspace& McpWorkspace::operator=(McpWorkspace&&) noexcept = default;

McpResult SolveMcp(const McpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z, const McpOptions& options,
                   McpWorkspace& workspace) {
  WorkspaceLease<DenseNewtonAlgebra> lease(static_cast<int>(z.size()), workspace.storage_->dense);
  return SolveMcpWith(f, num_free, row_scale, var_scale, z, options, lease, workspace.cancel_);
}

McpResult SolveMcp(const SparseMcpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z, const McpOptions& options,
                   McpWorkspace& workspace) {
  WorkspaceLease<SparseNewtonAlgebra> lease(static_cast<int>(z.size()), workspace.storage_->sparse);
  return SolveMcpWith(f, num_free, row_scale, var_scale, z, options, lease, workspace.cancel_);
}

McpResult SolveMcp(const McpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z,
                   const McpOptions& options) {
  McpWorkspace workspace;
  return SolveMcp(f, num_free, row_scale, var_scale, z, options, workspace);
}

McpResult SolveMcp(const SparseMcpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z,
                   const McpOptions& options) {
  McpWorkspace workspace;
  return SolveMcp(f, num_free, row_scale, var_scale, z, options, workspace);
}

}  // namespace ecpsim::engine
