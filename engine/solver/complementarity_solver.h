#pragma once
// A solver for mixed complementarity problems: semismooth Newton on the penalized
// Fischer–Burmeister reformulation with a non-monotone Armijo line search and Levenberg–Marquardt /
// gradient fallbacks (FORMULATION.md, "Solver guidance"), with a dense Jacobian (one body's MNCP,
// small islands) or a sparse one (large islands, whose cost then grows with their size).

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "common/cancel_flag.h"

namespace ecpsim::engine {

/// Find z with F_i(z) = 0 for i < num_free and 0 ≤ z_i ⊥ F_i(z) ≥ 0 for i ≥ num_free.
/// The callback returns F(z) and, when J is not null, the Jacobian ∂F/∂z; J then arrives n × n
/// and zero, so the callback may add its entries without clearing it first.
using McpFunction =
    std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J)>;

/// Column-major sparse matrix, the Jacobian of a SparseMcpFunction.
using SparseMatrix = Eigen::SparseMatrix<double>;
/// The same with a sparse Jacobian (compressed or not; entries outside its pattern are zero).
using SparseMcpFunction =
    std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd* F, SparseMatrix* J)>;

/// A problem-specific convergence measure of (z, F) (z and F unscaled); by default McpResidual
/// of the scaled problem.
using McpMeasure = std::function<double(const Eigen::VectorXd& z, const Eigen::VectorXd& F)>;

struct McpOptions {
  double tolerance = 1e-10;  // on the measure: dimensionless for the default McpResidual
  int max_iterations = 60;
  double fb_lambda = 0.9;      // penalized FB weight (Chen–Chen–Kanzow); 1 is plain FB
  int nonmonotone_memory = 5;  // Armijo reference = max of the last few merit values
  McpMeasure measure;          // empty: McpResidual with the solver's num_free and scales
  // keep the complementarity unknowns z_i (i ≥ num_free) ≥ 0 at every iterate (each trial point
  // of the line search is projected onto that orthant): no iterate can reach a stationary point
  // of the merit function with a negative multiplier (engine/README.md, "Impacts")
  bool project_nonnegative = false;
  // the Newton matrix's complementarity rows from the smoothed φ(a, b) with √(a² + b² + 2μ²),
  // μ = jacobian_smoothing × ‖Φ‖ (Chen–Qi–Sun's Jacobian smoothing): nonsingular where a pair is
  // degenerate (a contact touching with zero force); 0 is the plain generalized Jacobian
  double jacobian_smoothing = 0;
  // a Newton step the line search cuts short is compared with a Levenberg–Marquardt step whose
  // damping adapts like a trust region (engine/README.md, "Solver"): for problems whose solutions
  // are isolated but whose Newton matrix can be nearly singular; problems with non-isolated
  // solutions (the multi-patch model's) converge better on the plain iteration
  bool levenberg_marquardt_rescue = false;
  // factor the Newton matrix by replaying the elimination schedule of its non-zero pattern with
  // threshold pivoting (pattern_lu.h) instead of the dense partial-pivoting sweep: several times
  // cheaper from a few dozen unknowns (the multi-patch model's), the same solution to round-off
  // but other round-off, so iterates differ in their last bits (dense Jacobians only)
  bool replay_pivots = false;
  // the order in which the dense LU eliminates the unknowns (a symmetric permutation of the
  // Newton matrix, its rows and columns alike; partial pivoting as ever), empty: as they come.
  // Where many contacts share one body's velocities, eliminating the contacts' own unknowns
  // first and the velocities last keeps the contacts' blocks from filling each other (the
  // multi-patch desk's 62 × 62 matrix: 10 thousand multiply-adds instead of 38 thousand). Other
  // round-off than the natural order, the same solution to it (dense Jacobians only)
  std::vector<int> elimination_order;
  // stop, unconverged, when the measure has not halved for this many iterations (0: never):
  // for callers with other guesses to try, a stalled solve's remaining iterations are wasted
  int stall_iterations = 0;
  // the start is likely a solution already (a warm start of bodies at rest under unchanged
  // loads): F is evaluated alone first and the start accepted if it meets the tolerance, without
  // the Jacobian a first Newton step needs; else the solve goes on as without it (one more F)
  bool verify_start_first = false;
  // the start itself ends the solve only if its measure is at most this (and the tolerance): a
  // start made close to the solution by construction (the hull model's balanced starts)
  // is taken on by a Newton step to round-off, where Newton's steps end, instead of being
  // accepted anywhere under the tolerance (the step's solution, and trajectories with it, would
  // move by up to the tolerance)
  double start_tolerance = INFINITY;
  // the Newton direction is the minimum-norm least-squares solution of H d = −Φ, by a complete
  // orthogonal decomposition that takes pivots ≤ kMinimumNormRankTolerance of the largest as
  // zero, instead of the LU's: where the solutions are not isolated (ECPs of two contacts that
  // share one moment equation) H is singular along their set, and the LU's step runs along it
  // (engine/README.md, "Non-isolated solutions"). Dense O(n³) with a larger constant than the LU
  // (a sparse H is factored dense): for rescues, not for every step
  bool minimum_norm_steps = false;
  // a proximal-point term ε (x − x_k) in the scaled problem, in the factored Newton matrix only
  // (engine/README.md, "Non-isolated solutions"): 0 is off
  double proximal_weight = 0;
};

/// Relative rank threshold of McpOptions::minimum_norm_steps: a pivot of the complete orthogonal
/// decomposition at most this fraction of the largest is round-off of a singular direction. The
/// scaled Newton matrix has O(1) entries, and eliminating a few hundred of them leaves ≈ n ε
/// (1e-14 … 1e-13) on an exactly singular direction; a larger cut also drops directions that are
/// merely ill-conditioned. Measured (engine/README.md, "Non-isolated solutions"): the pile of
/// five dominoes settles with any of 1e-13 … 1e-8; with minimum-norm steps in every solve, the
/// T-bar push's first touch at h = 2.5e-5 s passed at 1e-13 and 1e-12 and stalled at 1e-10, 1e-8.
inline constexpr double kMinimumNormRankTolerance = 1e-13;

struct McpResult {
  bool converged = false;
  int iterations = 0;
  double residual = 0;  // the measure (McpResidual by default) at the returned z
};

/// The residual of the scaled problem (0 exactly at a solution): with x = z / var_scale and
/// F̃ = row_scale ⊙ F, max(max_{i<num_free} |F̃_i|, max_{i≥num_free} |min(x_i, F̃_i)|). When the
/// scales are the problem's own units (a body's length, velocity, impulse) it is dimensionless,
/// so one tolerance means the same for a millimetre and a kilometre body.
double McpResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& F, int num_free,
                   const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale);

/// The storage SolveMcp works in (its matrices, factorizations and iterates), owned by the caller
/// and kept from solve to solve, so that a solve of sizes seen before allocates nothing. One
/// solve at a time uses it; a solve started while it is in use (one nested in a callback), or a
/// dense one of more than a few hundred unknowns (whose matrices grow with their square), works
/// in storage of its own. Moving it keeps the storage; threads solving at once need one each.
class McpWorkspace {
 public:
  McpWorkspace();
  ~McpWorkspace();
  McpWorkspace(McpWorkspace&&) noexcept;
  McpWorkspace& operator=(McpWorkspace&&) noexcept;

  /// Solves in this workspace throw Cancelled at their next iteration once `flag` is raised
  /// (null: never; a caller's request to stop, common/cancel_flag.h).
  void StopOn(const CancelFlag* flag) { cancel_ = flag; }
  const CancelFlag* cancel() const { return cancel_; }

 private:
  struct Storage;
  std::unique_ptr<Storage> storage_;
  const CancelFlag* cancel_ = nullptr;
  friend McpResult SolveMcp(const McpFunction&, int, const Eigen::VectorXd&, const Eigen::VectorXd&,
                            Eigen::VectorXd&, const McpOptions&, McpWorkspace&);
  friend McpResult SolveMcp(const SparseMcpFunction&, int, const Eigen::VectorXd&,
                            const Eigen::VectorXd&, Eigen::VectorXd&, const McpOptions&,
                            McpWorkspace&);
};

/// Solves in place from the initial guess `z`. `row_scale` and `var_scale` (positive) define the
/// scaled problem F̃ = row_scale ⊙ F(var_scale ⊙ x) the Newton iteration works on, so rows and
/// unknowns of different units (N·s, m, dimensionless multipliers) weigh alike (trap 6); the
/// convergence test is `options.measure`, by default McpResidual of the same scaled problem
/// (relative to the scales, never an absolute bar). Never returns a non-finite z: if an iterate
/// would be non-finite the solve stops unconverged at the last finite iterate.
McpResult SolveMcp(const McpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z, const McpOptions& options,
                   McpWorkspace& workspace);

/// The same iteration with a sparse Jacobian: the Newton matrix is factored by a sparse LU with
/// a fill-reducing ordering and the Levenberg–Marquardt step solves the sparse normal equations,
/// so an iteration costs in proportion to the factors' fill (for a chain of bodies, to the
/// number of unknowns) instead of n³. Same options, same result up to the factorizations'
/// round-off.
McpResult SolveMcp(const SparseMcpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z, const McpOptions& options,
                   McpWorkspace& workspace);

/// SolveMcp in storage of its own for this one solve (allocates: for one-off solves).
McpResult SolveMcp(const McpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z,
                   const McpOptions& options = {});
McpResult SolveMcp(const SparseMcpFunction& f, int num_free, const Eigen::VectorXd& row_scale,
                   const Eigen::VectorXd& var_scale, Eigen::VectorXd& z,
                   const McpOptions& options = {});

}  // namespace ecpsim::engine
