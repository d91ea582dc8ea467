#pragma once
// LU with partial pivoting for the Newton matrix of one body's (or a small island's) MNCP: its
// non-zeros keep one pattern from iteration to iteration and step to step (the contact layout
// sets it), so the elimination's schedule — pivot rows, fill, which entries update which — is
// worked out once per pattern and replayed on the non-zeros alone (≈ 1,200 multiply-adds for the
// desk's 20 × 20 matrix instead of a dense sweep).

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

namespace ecpsim::engine {

/// Factors square matrices A = P⁻¹ L U and solves with them.
///
/// A matrix of a new pattern is eliminated densely (unblocked, right-looking, LAPACK's getf2
/// order) with partial pivoting, and the schedule of that elimination — its pivot rows and the
/// structural fill of the pattern under them — is kept (a few patterns at a time). A matrix
/// whose non-zeros lie within a kept pattern replays that schedule with threshold pivoting: each
/// recorded pivot must be at least a fixed fraction (0.1) of its column's largest candidate,
/// else the dense elimination runs and records the new pivots. A replay does the dense
/// elimination's floating-point operations for its pivots, entry by entry in the same order,
/// leaving out only x − l·u with l or u exactly 0: with the pivots the dense elimination would
/// choose it is bit-identical to it. A non-finite entry (in A or, by overflow, in the factors)
/// also goes the dense way. Matrices larger than kMaxUnblockedSize go to Eigen's blocked
/// PartialPivLU (faster there). The replay pays from a few dozen unknowns (the desk's 82-unknown
/// multi-patch MNCP: 3.5 × fewer instructions); at the 25 of one contact its index lists cost
/// about what the dense sweep's zero tests save. An exactly zero pivot is kept, so that
/// SolveInPlace returns a non-finite x the caller rejects, as Eigen's PartialPivLU does.
class PatternLu {
 public:
  /// The dense elimination's instruction set for matrices of 32 unknowns or more: the widest the
  /// processor has (AVX2 where there: the multi-patch desk's step 106 → 86 µs), or one of them
  /// (tests: both give the same bits; kAvx2 only where __builtin_cpu_supports("avx2")). Smaller
  /// ones, one contact's, always take a portable version, which was the faster there.
  enum class Kernel { kFastest, kPortable, kAvx2 };
  explicit PatternLu(Kernel kernel = Kernel::kFastest);

  /// Factors `A` (square); allocates only when a new pattern or size is seen. With `replay`
  /// false always by the dense elimination (partial pivoting, no schedule kept or used). With an
  /// `order` (a permutation of A's rows, its columns alike) the factors are those of P A Pᵀ, the
  /// order in which the unknowns are eliminated (McpOptions::elimination_order); empty: A's own.
  void Compute(const Eigen::MatrixXd& A, bool replay = true, const std::vector<int>& order = {});
  /// x ← A⁻¹ x (non-finite where A is singular), in A's order whatever the elimination's.
  void SolveInPlace(Eigen::VectorXd& x) const;
  /// Whether the last Compute replayed a cached schedule (false: dense or blocked elimination).
  bool replayed() const { return mode_ == Mode::kReplayed; }

  /// Side length up to which the unblocked elimination (dense or replayed) is used.
  static constexpr Eigen::Index kMaxUnblockedSize = 128;

 private:
  // the elimination worked out for one pattern and pivot sequence, in original row indices
  struct Schedule {
    Eigen::Index n = 0;
    std::vector<std::uint64_t> pattern;  // n columns × words: the rows A may have non-zero
    std::vector<Eigen::Index> pivots;    // per column k, the position swapped with k
    // per column k: the candidate rows of the pivot search, the recorded pivot row, the rows
    // below it (its multipliers) and the columns j > k the pivot row updates
    std::vector<int> candidate_begin, candidates, pivot_row;
    std::vector<int> lower_begin, lower_rows, upper_begin, upper_cols;
    // the triangular solves on the final positions: per column j its L entries (position,
    // offset in the column-major storage) below and U entries above the diagonal
    std::vector<int> solve_lower_begin, solve_lower_pos, solve_lower_offset;
    std::vector<int> solve_upper_begin, solve_upper_pos, solve_upper_offset, diagonal_offset;
  };
  enum class Mode { kDense, kReplayed, kBlocked };

  // a run of the elimination order: `length` consecutive positions from `target` of P A Pᵀ are
  // A's from `source`
  struct Run {
    Eigen::Index target, source, length;
  };

  static int Words(Eigen::Index n) { return static_cast<int>((n + 63) / 64); }
  void SetOrder(const std::vector<int>& order);
  // lu_ ← P A Pᵀ
  void Load(const Eigen::MatrixXd& A);
  // x ← (P A Pᵀ)⁻¹ x
  void SolveInOrder(Eigen::VectorXd& x) const;
  // the non-zero pattern of A into mask_ (n columns × Words(n))
  void ComputeMask(const Eigen::MatrixXd& A);
  // the cached schedule whose pattern holds mask_ (most recently used first), else null
  Schedule* FindSchedule(Eigen::Index n);
  bool Replay(const Schedule& s);
  void FactorDense();
  // the symbolic elimination of `pattern` under `pivots` (from FactorDense)
  static Schedule MakeSchedule(Eigen::Index n, std::vector<std::uint64_t> pattern,
                               const std::vector<Eigen::Index>& pivots);
  void Remember(Schedule schedule);

  // the schedules kept (a few layouts: a window that grows, an island that splits)
  static constexpr int kMaxSchedules = 4;

  bool wide_;               // the AVX2 version of the dense elimination (of large matrices)
  std::vector<int> order_;  // the elimination order (empty: A's)
  std::vector<Run> runs_;   // that order as runs of consecutive positions
  mutable Eigen::VectorXd permuted_x_;
  Mode mode_ = Mode::kDense;
  // dense: U in position order, each column of L in the row order of its elimination (the
  // interchanges of later columns not applied to it); replayed: the factors in original rows
  Eigen::MatrixXd lu_;
  std::vector<Eigen::Index> pivots_;
  const Schedule* replayed_ = nullptr;
  std::vector<Schedule> schedules_;  // most recently used first
  std::vector<std::uint64_t> mask_;
  Eigen::PartialPivLU<Eigen::MatrixXd> blocked_lu_;
};

}  // namespace ecpsim::engine
