#include "engine/solver/pattern_lu.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

// a replay keeps the recorded pivot while it is at least this fraction of its column's largest
// candidate: the threshold pivoting of sparse direct solvers (UMFPACK's default 0.1), whose
// growth of the factors stays bounded as partial pivoting's does in practice. Exact ties and
// near-ties (the Newton matrix's ±1 identity blocks against entries scaled to ≈ 1) change the
// strict partial-pivoting choice from one iteration to the next: on the desk, most
// factorizations chose another pivot somewhere than the one before
constexpr double kPivotThreshold = 0.1;

bool Has(const std::uint64_t* column, int row) { return (column[row / 64] >> (row % 64)) & 1; }
void Set(std::uint64_t* column, int row) { column[row / 64] |= std::uint64_t{1} << (row % 64); }

}  // namespace

void PatternLu::Compute(const Eigen::MatrixXd& A, bool replay, const std::vector<int>& order) {
  ECPSIM_DEMAND(A.rows() == A.cols());
  ECPSIM_DEMAND(order.empty() || static_cast<Eigen::Index>(order.size()) == A.rows());
  SetOrder(order);
  const Eigen::Index n = A.rows();
  if (n > kMaxUnblockedSize) {
    mode_ = Mode::kBlocked;
    if (order_.empty()) {
      blocked_lu_.compute(A);
    } else {
      Load(A);
      blocked_lu_.compute(lu_);
    }
    return;
  }
  Load(A);
  // a non-finite entry defeats the pivot comparisons and x − l·0 = x: the dense elimination
  // handles it as it always did
  if (!replay || !lu_.allFinite()) {
    FactorDense();
    return;
  }
  ComputeMask(lu_);
  Schedule* cached = FindSchedule(n);
  if (cached != nullptr && Replay(*cached)) return;
  // a new pattern, or another pivot sequence: eliminate densely and record what it did, on the
  // union with the last pattern of this size (zeros that come and go keep one schedule)
  if (cached == nullptr) {
    const auto same_size = std::find_if(schedules_.begin(), schedules_.end(),
                                        [&](const Schedule& s) { return s.n == n; });
    if (same_size != schedules_.end()) cached = &*same_size;
  }
  if (cached != nullptr)
    for (size_t w = 0; w < mask_.size(); ++w) mask_[w] |= cached->pattern[w];
  Load(A);
  FactorDense();
  Remember(MakeSchedule(n, mask_, pivots_));
}

void PatternLu::SetOrder(const std::vector<int>& order) {
  order_ = order;  // (its capacity kept from call to call)
  // the order's maximal runs of consecutive positions (a few: a model's blocks)
  runs_.clear();
  for (size_t i = 0; i < order.size(); ++i) {
    if (!runs_.empty() && order[i] == runs_.back().source + runs_.back().length) {
      ++runs_.back().length;
    } else {
      runs_.push_back({static_cast<Eigen::Index>(i), order[i], 1});
    }
  }
}

void PatternLu::Load(const Eigen::MatrixXd& A) {
  if (order_.empty()) {
    lu_ = A;
    return;
  }
  // P A Pᵀ, each column copied run by run
  const Eigen::Index n = A.rows();
  lu_.resize(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* source = A.col(order_[j]).data();
    double* target = lu_.col(j).data();
    for (const Run& run : runs_) std::copy_n(source + run.source, run.length, target + run.target);
  }
}

void PatternLu::ComputeMask(const Eigen::MatrixXd& A) {
  const Eigen::Index n = A.rows();
  const int words = Words(n);
  mask_.assign(n * words, 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* column = A.data() + j * n;
    std::uint64_t* bits = mask_.data() + j * words;
    for (Eigen::Index i = 0; i < n; ++i)
      if (column[i] != 0) Set(bits, static_cast<int>(i));
  }
}

PatternLu::Schedule* PatternLu::FindSchedule(Eigen::Index n) {
  for (size_t c = 0; c < schedules_.size(); ++c) {
    const Schedule& s = schedules_[c];
    if (s.n != n) continue;
    bool inside = true;
    for (size_t w = 0; w < mask_.size() && inside; ++w) inside = (mask_[w] & ~s.pattern[w]) == 0;
    if (!inside) continue;
    // most recently used first
    std::rotate(schedules_.begin(), schedules_.begin() + c, schedules_.begin() + c + 1);
    return &schedules_.front();
  }
  return nullptr;
}

bool PatternLu::Replay(const Schedule& s) {
  const Eigen::Index n = s.n;
  double* const a = lu_.data();
  for (Eigen::Index k = 0; k < n; ++k) {
    double* const col_k = a + k * n;
    // threshold partial pivoting: the recorded pivot row stays while its entry is at least
    // kPivotThreshold of the column's largest candidate
    const int* candidate = s.candidates.data() + s.candidate_begin[k];
    const int count = s.candidate_begin[k + 1] - s.candidate_begin[k];
    double largest = 0;
    for (int c = 0; c < count; ++c) largest = std::max(largest, std::abs(col_k[candidate[c]]));
    const int row = s.pivot_row[k];
    const double pivot = col_k[row];
    if (!(std::abs(pivot) >= kPivotThreshold * largest)) return false;
    // the multipliers, divided (not multiplied by the reciprocal) as the dense elimination does
    const int* lower = s.lower_rows.data() + s.lower_begin[k];
    const int lower_count = s.lower_begin[k + 1] - s.lower_begin[k];
    if (pivot != 0)
      for (int i = 0; i < lower_count; ++i) col_k[lower[i]] /= pivot;
    // the update of the columns the pivot row reaches
    for (int u = s.upper_begin[k]; u < s.upper_begin[k + 1]; ++u) {
      double* const col_j = a + s.upper_cols[u] * n;
      const double factor = col_j[row];
      if (factor == 0) continue;
      for (int i = 0; i < lower_count; ++i) col_j[lower[i]] -= col_k[lower[i]] * factor;
    }
  }
  // an overflow inside the elimination: the dense one would spread it to entries left out here
  if (!lu_.allFinite()) return false;
  mode_ = Mode::kReplayed;
  replayed_ = &s;
  return true;
}

namespace {

// the partial pivot of column `col` from row k on: the first row of the largest magnitude, NaNs
// never larger (k itself if col[k] is NaN), by one running maximum
[[gnu::always_inline]] inline Eigen::Index FirstOfLargestShort(const double* col, Eigen::Index k,
                                                               Eigen::Index n) {
  Eigen::Index pivot = k;
  double largest = std::abs(col[k]);
  for (Eigen::Index i = k + 1; i < n; ++i) {
    const double magnitude = std::abs(col[i]);
    if (magnitude > largest) {
      largest = magnitude;
      pivot = i;
    }
  }
  return pivot;
}

// the same for long columns: the largest in four independent running maxima first, then the
// first row that has it (one running maximum is a chain of dependent compares, a quarter of the
// multi-patch desk's elimination)
[[gnu::always_inline]] inline Eigen::Index FirstOfLargestLong(const double* col, Eigen::Index k,
                                                              Eigen::Index n) {
  const double first = std::abs(col[k]);
  if (std::isnan(first)) return k;
  double largest[4] = {first, first, first, first};
  Eigen::Index i = k + 1;
  for (; i + 4 <= n; i += 4)
    for (int lane = 0; lane < 4; ++lane) {
      const double magnitude = std::abs(col[i + lane]);
      largest[lane] = magnitude > largest[lane] ? magnitude : largest[lane];
    }
  for (; i < n; ++i) {
    const double magnitude = std::abs(col[i]);
    largest[0] = magnitude > largest[0] ? magnitude : largest[0];
  }
  double overall = largest[0];
  for (int lane = 1; lane < 4; ++lane) overall = largest[lane] > overall ? largest[lane] : overall;
  Eigen::Index row = k;
  while (std::abs(col[row]) != overall) ++row;
  return row;
}

// matrices from this size on take the elimination for sparse long columns (kSparse below) and,
// where the processor has it, its AVX2 version; at one contact's 17–25 unknowns the scans cost
// more than the zeros they skip (callgrind, the hull desk: 2 % more instructions a step)
constexpr Eigen::Index kMinSparseSize = 32;

// LU with partial pivoting, unblocked (right-looking), on the column-major n × n matrix `a`,
// its interchanges into `pivots`. The multipliers x / p are divided (not multiplied by the
// reciprocal) as Eigen does: the multi-patch model's ill-conditioned systems take other Newton
// paths on the reciprocal's round-off. The update skips columns whose pivot-row entry is 0 and
// rows below the last non-zero multiplier (x − l·0 = x and x − 0·u = x for finite l, u); with
// kSparse (large matrices, whose columns are mostly zeros: the multi-patch desk's 62 × 62 is 5 %
// non-zeros) also the rows above the first, and the zeros outside the two are not divided but
// multiplied by p's sign (the same ±0; a division costs as much as the update). Inlined into
// each instruction set's version below
template <bool kSparse>
[[gnu::always_inline]] inline void EliminateDense(double* const a, const Eigen::Index n,
                                                  Eigen::Index* const pivots) {
  for (Eigen::Index k = 0; k < n; ++k) {
    double* const col_k = a + k * n;
    const Eigen::Index pivot =
        kSparse ? FirstOfLargestLong(col_k, k, n) : FirstOfLargestShort(col_k, k, n);
    pivots[k] = pivot;
    // the rows' entries from column k on: L's columns keep the row order of their own
    // elimination (LINPACK's storage), and SolveInPlace interchanges as it goes
    if (col_k[pivot] != 0 && pivot != k)
      for (Eigen::Index j = k; j < n; ++j) std::swap(a[j * n + k], a[j * n + pivot]);
    Eigen::Index begin = k + 1, end = n;
    const double p = col_k[k];
    if (p != 0) {
      if (kSparse && !std::isnan(p)) {
        while (end > begin && col_k[end - 1] == 0) --end;
        while (begin < end && col_k[begin] == 0) ++begin;
      }
      const double sign = std::copysign(1.0, p);
      for (Eigen::Index i = k + 1; i < begin; ++i) col_k[i] *= sign;
      for (Eigen::Index i = begin; i < end; ++i) col_k[i] /= p;
      for (Eigen::Index i = end; i < n; ++i) col_k[i] *= sign;
    }
    // (a quotient may underflow to 0)
    while (end > begin && col_k[end - 1] == 0) --end;
    if (kSparse)
      while (begin < end && col_k[begin] == 0) ++begin;
    if (begin == end) continue;  // no multipliers: nothing to update
    const Eigen::Index count = end - begin;
    const double* const multipliers = col_k + begin;
    for (double* col_j = col_k + n; col_j != a + n * n; col_j += n) {
      const double u = col_j[k];
      if (u == 0) continue;
      double* const below = col_j + begin;
      for (Eigen::Index i = 0; i < count; ++i) below[i] -= multipliers[i] * u;
    }
  }
}

void EliminateSmall(double* a, Eigen::Index n, Eigen::Index* pivots) {
  EliminateDense<false>(a, n, pivots);
}

void EliminateLargePortable(double* a, Eigen::Index n, Eigen::Index* pivots) {
  EliminateDense<true>(a, n, pivots);
}

// the update's column loop four doubles wide. AVX2 alone, not FMA: the product and the
// difference stay two roundings, so that both versions give the same bits. For large matrices
// only: at the hull desk's 17 unknowns the engine benchmark's step was 2–3 % slower with it
__attribute__((target("avx2"))) void EliminateLargeAvx2(double* a, Eigen::Index n,
                                                        Eigen::Index* pivots) {
  EliminateDense<true>(a, n, pivots);
}

}  // namespace

PatternLu::PatternLu(Kernel kernel)
    : wide_(kernel == Kernel::kAvx2 ||
            (kernel == Kernel::kFastest && __builtin_cpu_supports("avx2"))) {}

void PatternLu::FactorDense() {
  mode_ = Mode::kDense;
  const Eigen::Index n = lu_.rows();
  pivots_.resize(n);
  if (n < kMinSparseSize) {
    EliminateSmall(lu_.data(), n, pivots_.data());
  } else if (wide_) {
    EliminateLargeAvx2(lu_.data(), n, pivots_.data());
  } else {
    EliminateLargePortable(lu_.data(), n, pivots_.data());
  }
}

PatternLu::Schedule PatternLu::MakeSchedule(Eigen::Index n, std::vector<std::uint64_t> pattern,
                                            const std::vector<Eigen::Index>& pivots) {
  Schedule s;
  s.n = n;
  s.pivots = pivots;
  const int words = Words(n);
  // the structure evolves with the fill; position → original row as the rows are swapped
  std::vector<std::uint64_t> structure = pattern;
  s.pattern = std::move(pattern);
  std::vector<int> row_at(n);
  for (int i = 0; i < n; ++i) row_at[i] = i;
  std::vector<std::uint64_t> lower_mask(words);
  s.candidate_begin.push_back(0);
  s.lower_begin.push_back(0);
  s.upper_begin.push_back(0);
  for (int k = 0; k < n; ++k) {
    const std::uint64_t* column = structure.data() + k * words;
    // the pivot search's rows: the one at position k (outside the structure it holds an exact 0)
    // and the structural ones below
    s.candidates.push_back(row_at[k]);
    for (int p = k + 1; p < n; ++p)
      if (Has(column, row_at[p])) s.candidates.push_back(row_at[p]);
    s.candidate_begin.push_back(static_cast<int>(s.candidates.size()));
    std::swap(row_at[k], row_at[pivots[k]]);
    const int row = row_at[k];
    s.pivot_row.push_back(row);
    // the multipliers' rows and the columns the pivot row reaches; those take on the fill
    std::fill(lower_mask.begin(), lower_mask.end(), 0);
    for (int p = k + 1; p < n; ++p) {
      if (!Has(column, row_at[p])) continue;
      s.lower_rows.push_back(row_at[p]);
      Set(lower_mask.data(), row_at[p]);
    }
    s.lower_begin.push_back(static_cast<int>(s.lower_rows.size()));
    for (int j = k + 1; j < n; ++j) {
      std::uint64_t* target = structure.data() + j * words;
      if (!Has(target, row)) continue;
      s.upper_cols.push_back(j);
      for (int w = 0; w < words; ++w) target[w] |= lower_mask[w];
    }
    s.upper_begin.push_back(static_cast<int>(s.upper_cols.size()));
  }
  // the triangular solves on the final positions
  std::vector<int> position(n);
  for (int p = 0; p < n; ++p) position[row_at[p]] = p;
  s.solve_lower_begin.push_back(0);
  s.solve_upper_begin.push_back(0);
  for (int j = 0; j < n; ++j) {
    const std::uint64_t* column = structure.data() + j * words;
    s.diagonal_offset.push_back(static_cast<int>(row_at[j] + j * n));
    for (int r = 0; r < n; ++r) {
      if (!Has(column, r) || position[r] == j) continue;
      const bool lower = position[r] > j;
      (lower ? s.solve_lower_pos : s.solve_upper_pos).push_back(position[r]);
      (lower ? s.solve_lower_offset : s.solve_upper_offset).push_back(static_cast<int>(r + j * n));
    }
    s.solve_lower_begin.push_back(static_cast<int>(s.solve_lower_pos.size()));
    s.solve_upper_begin.push_back(static_cast<int>(s.solve_upper_pos.size()));
  }
  return s;
}

void PatternLu::Remember(Schedule schedule) {
  // replaces the one whose pattern it extends, else the least recently used
  const auto same = std::find_if(schedules_.begin(), schedules_.end(), [&](const Schedule& s) {
    if (s.n != schedule.n) return false;
    for (size_t w = 0; w < s.pattern.size(); ++w)
      if ((s.pattern[w] & ~schedule.pattern[w]) != 0) return false;
    return true;
  });
  if (same != schedules_.end()) {
    schedules_.erase(same);
  } else if (static_cast<int>(schedules_.size()) >= kMaxSchedules) {
    schedules_.pop_back();
  }
  schedules_.insert(schedules_.begin(), std::move(schedule));
}

void PatternLu::SolveInPlace(Eigen::VectorXd& x) const {
  if (!order_.empty()) {
    // P x, solved with the factors of P A Pᵀ, then back to A's order
    permuted_x_.resize(x.size());
    for (Eigen::Index i = 0; i < x.size(); ++i) permuted_x_[i] = x[order_[i]];
    SolveInOrder(permuted_x_);
    for (Eigen::Index i = 0; i < x.size(); ++i) x[order_[i]] = permuted_x_[i];
    return;
  }
  SolveInOrder(x);
}

void PatternLu::SolveInOrder(Eigen::VectorXd& x) const {
  if (mode_ == Mode::kBlocked) {
    x = blocked_lu_.solve(Eigen::VectorXd(x));
    return;
  }
  const Eigen::Index n = lu_.rows();
  const double* const a = lu_.data();
  if (mode_ == Mode::kReplayed) {
    // the row interchanges, then the same operations as below on the structural entries only
    // (in any order within a column: each x[p] still takes its terms in the order of j)
    const Schedule& s = *replayed_;
    for (Eigen::Index k = 0; k < n; ++k) std::swap(x[k], x[s.pivots[k]]);
    for (Eigen::Index j = 0; j < n; ++j) {
      const double xj = x[j];
      if (xj == 0) continue;
      for (int e = s.solve_lower_begin[j]; e < s.solve_lower_begin[j + 1]; ++e)
        x[s.solve_lower_pos[e]] -= a[s.solve_lower_offset[e]] * xj;
    }
    for (Eigen::Index j = n - 1; j >= 0; --j) {
      x[j] /= a[s.diagonal_offset[j]];
      const double xj = x[j];
      if (xj == 0) continue;
      for (int e = s.solve_upper_begin[j]; e < s.solve_upper_begin[j + 1]; ++e)
        x[s.solve_upper_pos[e]] -= a[s.solve_upper_offset[e]] * xj;
    }
    return;
  }
  // the unit lower triangular solve with the row interchanges as the elimination made them (L
  // as FactorDense left it: each entry still takes the same terms in the same order as after all
  // interchanges up front), then the upper one; column-oriented (Eigen's triangular solve
  // allocates a temporary for dynamic vectors). No test for x_j = 0 (x − l·0 = x for finite l):
  // its branch waits on the division before it, and dropping it took the engine benchmark's
  // hull desk step from 3.07–3.13 to 2.98–3.07 µs, every trajectory bit-identical
  for (Eigen::Index j = 0; j < n; ++j) {
    std::swap(x[j], x[pivots_[j]]);
    const double xj = x[j];
    for (Eigen::Index i = j + 1; i < n; ++i) x[i] -= a[j * n + i] * xj;
  }
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    x[j] /= a[j * n + j];
    const double xj = x[j];
    for (Eigen::Index i = 0; i < j; ++i) x[i] -= a[j * n + i] * xj;
  }
}

}  // namespace ecpsim::engine
