#include "engine/solver/sparse_factorizations.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <amd.h>
#include <klu.h>

namespace ecpsim::engine {

bool SparsityPattern::Update(const Eigen::SparseMatrix<double>& A) {
  const bool same = static_cast<Eigen::Index>(outer_.size()) == A.outerSize() + 1 &&
                    static_cast<Eigen::Index>(inner_.size()) == A.nonZeros() &&
                    std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
                    std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
  if (same) return false;
  outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
  inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  return true;
}

bool PatternCover::Covers(const Eigen::SparseMatrix<double>& A) const {
  if (covered_.rows() != A.rows() || covered_.cols() != A.cols()) return false;
  const int* a_outer = A.outerIndexPtr();
  const int* a_inner = A.innerIndexPtr();
  const int* c_outer = covered_.outerIndexPtr();
  const int* c_inner = covered_.innerIndexPtr();
  if (exact_only_)
    return covered_.nonZeros() == A.nonZeros() &&
           std::equal(c_outer, c_outer + A.cols() + 1, a_outer) &&
           std::equal(c_inner, c_inner + A.nonZeros(), a_inner);
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    // A's column is a subsequence of the covered one (both sorted)
    int c = c_outer[j];
    for (int a = a_outer[j]; a < a_outer[j + 1]; ++a, ++c) {
      while (c < c_outer[j + 1] && c_inner[c] < a_inner[a]) ++c;
      if (c == c_outer[j + 1] || c_inner[c] != a_inner[a]) return false;
    }
  }
  return true;
}

const Eigen::SparseMatrix<double>& PatternCover::Cover(const Eigen::SparseMatrix<double>& A,
                                                       bool* analyse) {
  const bool covers = Covers(A);
  *analyse = !covers;
  if (!covers) {
    const bool unite = !exact_only_ && covered_.rows() == A.rows() && covered_.cols() == A.cols();
    Eigen::SparseMatrix<double> united;
    if (unite) {
      // (the union's values are A's: the sum of the two patterns' indicator, with A's values
      // written over it below)
      united = covered_.cwiseAbs() + A.cwiseAbs();
    }
    if (unite && united.nonZeros() <= kMaxGrowth * A.nonZeros()) {
      covered_ = std::move(united);
    } else {
      covered_ = A;
      covered_.makeCompressed();
      exact_only_ = false;
      return covered_;
    }
  }
  exact_only_ = false;
  // A's values on the covered pattern, zeros elsewhere
  const int* a_outer = A.outerIndexPtr();
  const int* a_inner = A.innerIndexPtr();
  const double* a_value = A.valuePtr();
  const int* c_outer = covered_.outerIndexPtr();
  const int* c_inner = covered_.innerIndexPtr();
  double* c_value = covered_.valuePtr();
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    int a = a_outer[j];
    for (int c = c_outer[j]; c < c_outer[j + 1]; ++c) {
      if (a < a_outer[j + 1] && a_inner[a] == c_inner[c]) {
        c_value[c] = a_value[a++];
      } else {
        c_value[c] = 0;
      }
    }
  }
  return covered_;
}

// KLU's state: its settings, the symbolic analysis of the current pattern and the numeric
// factors of the last matrix
struct SparseLu::Klu {
  klu_common common;
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
  int n = 0;
  // the numeric factors reuse the pivots of an earlier matrix of the solve (klu_refactor)
  bool reused_pivots = false;

  Klu() {
    klu_defaults(&common);
    common.tol = SparseLu::kPivotTolerance;
  }
  ~Klu() {
    FreeNumeric();
    if (symbolic) klu_free_symbolic(&symbolic, &common);
  }
  void FreeNumeric() {
    if (numeric) klu_free_numeric(&numeric, &common);
  }
};

SparseLu::SparseLu() : klu_(std::make_unique<Klu>()) {}
SparseLu::~SparseLu() = default;

bool SparseLu::Factor(const Eigen::SparseMatrix<double>& matrix) {
  Klu& k = *klu_;
  bool analyse = false;
  const Eigen::SparseMatrix<double>& A = pattern_.Cover(matrix, &analyse);
  factored_ = &A;
  // a new analysis, or a new solve, starts from pivots of its own
  if (analyse || !pivots_of_solve_) k.FreeNumeric();
  if (analyse) {
    if (k.symbolic) klu_free_symbolic(&k.symbolic, &k.common);
    k.n = static_cast<int>(A.rows());
    // (KLU's arguments are not const-qualified; it reads them only)
    k.symbolic = klu_analyze(k.n, const_cast<int*>(A.outerIndexPtr()),
                             const_cast<int*>(A.innerIndexPtr()), &k.common);
  }
  if (!k.symbolic) {
    pattern_ = PatternCover();  // analysed again next time
    return false;
  }
  pivots_of_solve_ = true;
  if (k.numeric != nullptr &&
      klu_refactor(const_cast<int*>(A.outerIndexPtr()), const_cast<int*>(A.innerIndexPtr()),
                   const_cast<double*>(A.valuePtr()), k.symbolic, k.numeric, &k.common)) {
    k.reused_pivots = true;
    return true;
  }
  return FactorWithOwnPivots();
}

bool SparseLu::FactorWithOwnPivots() {
  Klu& k = *klu_;
  const Eigen::SparseMatrix<double>& A = *factored_;
  k.FreeNumeric();
  k.numeric = klu_factor(const_cast<int*>(A.outerIndexPtr()), const_cast<int*>(A.innerIndexPtr()),
                         const_cast<double*>(A.valuePtr()), k.symbolic, &k.common);
  k.reused_pivots = false;
  return k.numeric != nullptr;
}

void SparseLu::SolveInPlace(Eigen::VectorXd& x) {
  Klu& k = *klu_;
  if (!k.reused_pivots) {
    klu_solve(k.symbolic, k.numeric, k.n, 1, x.data(), &k.common);
    return;
  }
  rhs_ = x;
  klu_solve(k.symbolic, k.numeric, k.n, 1, x.data(), &k.common);
  // the solve's backward error: reused pivots can be small ones of this matrix, whose growth
  // only the residual shows
  residual_ = rhs_;
  residual_.noalias() -= *factored_ * x;
  const double largest_entry =
      Eigen::Map<const Eigen::VectorXd>(factored_->valuePtr(), factored_->nonZeros())
          .lpNorm<Eigen::Infinity>();
  const double scale = largest_entry * x.lpNorm<Eigen::Infinity>() + rhs_.lpNorm<Eigen::Infinity>();
  // (a non-finite x or residual fails the test)
  if (residual_.lpNorm<Eigen::Infinity>() <= kReusedPivotsBackwardError * scale) return;
  x = rhs_;
  if (!FactorWithOwnPivots()) {
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  klu_solve(k.symbolic, k.numeric, k.n, 1, x.data(), &k.common);
}

void DampedLeastSquares::AmdOrdering::operator()(const Eigen::SparseMatrix<double>& symmetric,
                                                 PermutationType& order) {
  const int n = static_cast<int>(symmetric.cols());
  order.resize(n);
  if (!symmetric.isCompressed()) {
    Eigen::SparseMatrix<double> compressed = symmetric;
    compressed.makeCompressed();
    operator()(compressed, order);
    return;
  }
  // (amd_order takes A + Aᵀ's pattern itself; a result other than AMD_OK or AMD_OK_BUT_JUMBLED
  // is out of memory, where the identity is still a valid order)
  const int status = amd_order(n, symmetric.outerIndexPtr(), symmetric.innerIndexPtr(),
                               order.indices().data(), nullptr, nullptr);
  if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED) order.setIdentity(n);
}

void DampedLeastSquares::Solve(const Eigen::SparseMatrix<double>& H, double mu,
                               const Eigen::VectorXd& gradient, Eigen::VectorXd& direction) {
  if (SolveAugmented(H, mu, gradient, direction)) return;
  SolveNormal(H, mu, gradient, direction);
}

bool DampedLeastSquares::SolveAugmented(const Eigen::SparseMatrix<double>& H, double mu,
                                        const Eigen::VectorXd& gradient,
                                        Eigen::VectorXd& direction) {
  const int m = static_cast<int>(H.rows()), n = static_cast<int>(H.cols());
  rows_ = H;
  rows_.makeCompressed();
  // K's lower triangle by columns: column i < m holds 1 on the diagonal and row i of H below it
  // (at rows m + j), column m + j the diagonal −μ alone
  augmented_.resize(m + n, m + n);
  augmented_.resizeNonZeros(static_cast<Eigen::Index>(rows_.nonZeros()) + m + n);
  int* outer = augmented_.outerIndexPtr();
  int* inner = augmented_.innerIndexPtr();
  double* value = augmented_.valuePtr();
  int k = 0;
  for (int i = 0; i < m; ++i) {
    outer[i] = k;
    inner[k] = i;
    value[k++] = 1;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows_, i); it; ++it) {
      inner[k] = m + static_cast<int>(it.col());
      value[k++] = it.value();
    }
  }
  for (int j = 0; j < n; ++j) {
    outer[m + j] = k;
    inner[k] = m + j;
    value[k++] = -mu;
  }
  outer[m + n] = k;
  bool analyse = false;
  const Eigen::SparseMatrix<double>& K = augmented_pattern_.Cover(augmented_, &analyse);
  if (analyse) augmented_ldlt_.analyzePattern(K);
  augmented_ldlt_.factorize(K);
  if (augmented_ldlt_.info() != Eigen::Success) return false;

  rhs_.setZero(m + n);
  rhs_.tail(n) = gradient;
  solution_ = augmented_ldlt_.solve(rhs_);
  // one step of iterative refinement on the full symmetric system
  correction_ = rhs_;
  correction_.noalias() -= augmented_.selfadjointView<Eigen::Lower>() * solution_;
  solution_ += augmented_ldlt_.solve(correction_);
  direction = solution_.tail(n);
  // the normal equations' residual (HᵀH + μI) d + g, the measure the fallback is held to
  product_.noalias() = H * direction;
  normal_residual_.noalias() = H.transpose() * product_;
  normal_residual_ += mu * direction + gradient;
  const double error = normal_residual_.norm();
  return std::isfinite(error) && error <= kAugmentedRelTolerance * gradient.norm();
}

void DampedLeastSquares::SolveNormal(const Eigen::SparseMatrix<double>& H, double mu,
                                     const Eigen::VectorXd& gradient, Eigen::VectorXd& direction) {
  normal_ = H.transpose() * H;
  for (Eigen::Index j = 0; j < normal_.cols(); ++j) normal_.coeffRef(j, j) += mu;
  normal_.makeCompressed();
  if (normal_pattern_.Update(normal_)) normal_ldlt_.analyzePattern(normal_);
  normal_ldlt_.factorize(normal_);
  if (normal_ldlt_.info() != Eigen::Success) {
    direction.setConstant(gradient.size(), std::numeric_limits<double>::quiet_NaN());
    return;
  }
  direction = normal_ldlt_.solve(-gradient);
}

}  // namespace ecpsim::engine
