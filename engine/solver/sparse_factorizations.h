#pragma once
// The sparse Newton matrix's two factorizations (engine/README.md, "The island's linear
// algebra"): its LU for the Newton direction, and the Levenberg–Marquardt direction's damped
// least squares. Each keeps its analysis (ordering, symbolic factorization) while the matrices'
// non-zeros stay within the pattern it was made for.

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace ecpsim::engine {

/// The non-zero pattern a sparse factorization was analysed for: its fill-reducing ordering and
/// symbolic factorization depend on nothing else, so they are redone only when it changes.
class SparsityPattern {
 public:
  /// true when `A`'s compressed pattern differs from the last one (which it then becomes)
  bool Update(const Eigen::SparseMatrix<double>& A);

 private:
  std::vector<int> outer_, inner_;
};

/// The pattern a factorization was analysed for, covering the Newton matrices of one solve:
/// their non-zeros move from iteration to iteration (an entry of the reformulation's derivative
/// turns exactly zero on one side of a kink), and analysing each anew costs as much as factoring
/// it. A matrix whose non-zeros lie within the analysed pattern is laid on it, with explicit
/// zeros, and factored with the analysis kept; one with a non-zero outside analyses the union
/// of both, or (where the union would hold more than kMaxGrowth × its non-zeros) its own. So
/// that the factors depend on the solve alone, never on what the thread solved before, a solve
/// starts (BeginSolve) by keeping the analysis only for a matrix of exactly its pattern.
class PatternCover {
 public:
  /// the union is analysed while it holds at most this many times the matrix's non-zeros: the
  /// zeros added cost fill in the factors
  static constexpr double kMaxGrowth = 1.5;

  void BeginSolve() { exact_only_ = true; }
  /// `A` (compressed, columns sorted) on the analysed pattern; *analyse is set when that pattern
  /// changed and the factorization must analyse it again.
  const Eigen::SparseMatrix<double>& Cover(const Eigen::SparseMatrix<double>& A, bool* analyse);

 private:
  bool Covers(const Eigen::SparseMatrix<double>& A) const;

  Eigen::SparseMatrix<double> covered_;
  bool exact_only_ = true;
};

/// LU of a square sparse matrix by SuiteSparse's KLU: block triangular form, AMD ordering of
/// each block and partial pivoting within it. An island's Newton matrix — bodies' 6 × 6 blocks
/// coupled through their contacts' blocks — has the structure KLU is made for: on the 24-box
/// bin's 2,450-unknown island it factors in about 20 ms where Eigen's supernodal SparseLU
/// (COLAMD) takes 48. Within a solve (from one BeginSolve to the next) a matrix on the analysed
/// pattern is factored with the pivots of the solve's last pivoted factorization (klu_refactor,
/// no pivot search), and factored with pivots of its own only where the solve by the reused ones
/// leaves a backward error above kReusedPivotsBackwardError.
class SparseLu {
 public:
  /// A pivot is taken on the diagonal only where it is at least this fraction of its column's
  /// largest: 1 is partial pivoting, as Eigen's SparseLU (and SuperLU by default) pivot. KLU's
  /// own default, 1e-3, made for circuit matrices that are nearly diagonally dominant, keeps
  /// small diagonal pivots that the complementarity rows of a pile's Newton matrix have, and
  /// its steps failed a step that partial pivoting solves (scenes/dominoes.yaml under `model:
  /// hull` at h = 0.01 s).
  static constexpr double kPivotTolerance = 1.0;
  /// A solve by reused pivots stands where ‖A x − b‖∞ ≤ this × (‖A‖max ‖x‖∞ + ‖b‖∞): partial
  /// pivoting's own backward error on the islands' Newton matrices, with room (engine/README.md,
  /// "The island's linear algebra"); above it the pivots no longer fit the matrix.
  static constexpr double kReusedPivotsBackwardError = 1e-13;

  SparseLu();
  ~SparseLu();
  SparseLu(const SparseLu&) = delete;
  SparseLu& operator=(const SparseLu&) = delete;

  /// A new solve's first matrix (PatternCover::BeginSolve), factored with pivots of its own: the
  /// factors depend on the solve alone.
  void BeginSolve() {
    pattern_.BeginSolve();
    pivots_of_solve_ = false;
  }
  /// Factors `A` (compressed, square, columns sorted); false where it is singular to a zero
  /// pivot.
  bool Factor(const Eigen::SparseMatrix<double>& A);
  /// x ← A⁻¹ x with the last successful Factor; not finite where `A` proves singular to a zero
  /// pivot of its own.
  void SolveInPlace(Eigen::VectorXd& x);

 private:
  bool FactorWithOwnPivots();  // of *factored_, with partial pivoting

  struct Klu;
  std::unique_ptr<Klu> klu_;
  PatternCover pattern_;  // the pattern klu_'s symbolic analysis was made for
  const Eigen::SparseMatrix<double>* factored_ = nullptr;  // the last Factor's matrix (pattern_'s)
  bool pivots_of_solve_ = false;    // klu_'s numeric factors, if any, are this solve's
  Eigen::VectorXd rhs_, residual_;  // a solve by reused pivots' right-hand side and residual
};

/// The Levenberg–Marquardt direction d = −(HᵀH + μI)⁻¹ g of a sparse square H, μ > 0.
/// The normal matrix HᵀH couples every two unknowns that share a row: all the contacts of a body
/// through its Newton–Euler rows, so on a pile it is dense in blocks (the 24-box bin: 445k
/// non-zeros for 40k in H, 84 ms to factor). The same d solves the augmented system
/// [I H; Hᵀ −μI] [r; d] = [0; g], as sparse as H: quasi-definite, so its LDLᵀ exists in any
/// symmetric order (Vanderbei 1995), and AMD's is several times cheaper than the normal
/// matrix's. Its pivots are of order μ, so its accuracy falls with μ: one step of iterative
/// refinement is taken, and where the normal equations' residual is still above
/// kAugmentedRelTolerance of ‖g‖ (μ = ‖Φ‖² below about 1e-14: the last iterations of a solve
/// that Newton's LU could not take) the normal matrix is factored instead.
class DampedLeastSquares {
 public:
  /// ‖(HᵀH + μI) d + g‖ ≤ this × ‖g‖ for the augmented system's d to be used: far below what a
  /// descent direction for the line search needs, and within 10× of the normal equations' own
  /// round-off on the bin's matrices down to μ = 1e-14 (1.3e-10 there).
  static constexpr double kAugmentedRelTolerance = 1e-9;

  /// A new solve's first matrix (PatternCover::BeginSolve).
  void BeginSolve() { augmented_pattern_.BeginSolve(); }
  /// direction ← −(HᵀH + μI)⁻¹ gradient; not finite where neither factorization succeeds.
  void Solve(const Eigen::SparseMatrix<double>& H, double mu, const Eigen::VectorXd& gradient,
             Eigen::VectorXd& direction);

 private:
  // SuiteSparse's AMD, several times faster than Eigen's port on these patterns
  struct AmdOrdering {
    using PermutationType = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;
    void operator()(const Eigen::SparseMatrix<double>& symmetric, PermutationType& order);
  };
  using Ldlt = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, AmdOrdering>;
  bool SolveAugmented(const Eigen::SparseMatrix<double>& H, double mu,
                      const Eigen::VectorXd& gradient, Eigen::VectorXd& direction);
  void SolveNormal(const Eigen::SparseMatrix<double>& H, double mu, const Eigen::VectorXd& gradient,
                   Eigen::VectorXd& direction);

  Eigen::SparseMatrix<double, Eigen::RowMajor> rows_;  // H by rows: K's lower columns
  Eigen::SparseMatrix<double> augmented_;              // K's lower triangle
  Ldlt augmented_ldlt_;
  PatternCover augmented_pattern_;
  Eigen::VectorXd rhs_, solution_, correction_;
  Eigen::VectorXd product_, normal_residual_;  // H d, and (HᵀH + μI) d + g
  Eigen::SparseMatrix<double> normal_;         // HᵀH + μI
  Ldlt normal_ldlt_;
  SparsityPattern normal_pattern_;
};

}  // namespace ecpsim::engine
